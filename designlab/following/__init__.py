"""following (to be filled by later issues)."""
