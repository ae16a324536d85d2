"""The generators of the generated views: one data file, several views (docs/conventions.md)."""
