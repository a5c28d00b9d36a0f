"""TALK-Dem inside other evaluation frameworks (optional extras, imported only when used)."""
