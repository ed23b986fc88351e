"""max2code runtime: root solvers and simulator (Python)."""
