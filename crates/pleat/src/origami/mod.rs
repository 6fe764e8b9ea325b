//! Origami: crease-pattern importers, the triangulated sheet and built-in patterns.
