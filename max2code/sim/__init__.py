"""Simulating: scenes (checked and compiled), building and running the
runtimes' simulators, replaying traces and checking their invariants."""
