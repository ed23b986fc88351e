"""Harnesses: the runtime libraries built for generated code, and small
programs per language that call generated entries (for the conformance
suite and the reports)."""
