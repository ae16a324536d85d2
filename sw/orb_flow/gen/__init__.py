"""The generators of the generated views: one source per shared fact (docs/conventions.md)."""
