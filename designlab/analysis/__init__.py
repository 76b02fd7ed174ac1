"""analysis (to be filled by later issues)."""
