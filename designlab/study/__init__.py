"""study (to be filled by later issues)."""
