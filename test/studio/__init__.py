"""The studio's tests: its API against the CLI, and its page in a real browser."""
