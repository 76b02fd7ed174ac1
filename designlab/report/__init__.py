"""report (to be filled by later issues)."""
