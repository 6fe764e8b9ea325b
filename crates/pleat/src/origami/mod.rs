//! Origami: crease-pattern importers, the triangulated sheet and built-in patterns.
//!
//! A pattern file (ORIPA `.cp`, FOLD `.fold`, Origami Simulator `.svg`) is read
//! into a [`CreasePattern`], cleaned into a planar graph ([`planar`]) and
//! triangulated into a [`Sheet`] whose creases are hinges.

pub mod builtin;
pub mod cp;
pub mod fold;
mod path_data;
pub mod pattern;
pub mod planar;
pub mod sheet;
pub mod svg;

pub use builtin::{builtin, Kresling, MiuraOri, BUILTIN_NAMES};
pub use cp::parse_cp;
pub use fold::{parse_fold, to_fold_json};
pub use pattern::{
    load_pattern, load_pattern_with_warnings, Assignment, CreasePattern, PatternEdge, PatternError,
};
pub use sheet::{Hinge, Sheet, SheetOptions};
pub use svg::{parse_svg, SvgImport};
