"""navigation (to be filled by later issues)."""
