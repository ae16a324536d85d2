"""The flow: synthesis, timing, board build checks and the generators of the generated views (docs/conventions.md)."""
