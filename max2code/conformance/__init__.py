"""Conformance suite: cases in tests/conformance/*.jsonl, one testee per runtime."""
