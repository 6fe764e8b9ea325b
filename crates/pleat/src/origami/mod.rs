//! Origami formats: crease-pattern importers, the triangulated sheet and
//! built-in patterns, below the physics (nothing here imports it).
//!
//! A pattern file (ORIPA `.cp`, FOLD `.fold`, Origami Simulator `.svg`) is read
//! into a [`CreasePattern`], cleaned into a planar graph ([`planar`]) and
//! triangulated into a [`Sheet`] whose creases are hinges;
//! [`crate::folding`] adds the sheet to a model as paper ([`crate::paper`])
//! and drives its hinges by the fold progress.

pub mod builtin;
pub mod cp;
pub mod flat_fold;
pub mod flat_foldability;
pub mod fold;
pub mod load;
mod path_data;
pub mod pattern;
pub mod planar;
pub mod sheet;
pub mod svg;
mod unfold;

pub use builtin::{builtin, Kresling, MiuraOri, BUILTIN_NAMES};
pub use cp::parse_cp;
pub use flat_fold::{FacetSides, FlatFolded, LayerCheck};
pub use flat_foldability::{check_flat_foldability, FlatFoldability, Theorem, Violation};
pub use fold::{parse_fold, parse_fold_frames, parse_fold_with_warnings, to_fold_json};
pub use load::{load_pattern, load_pattern_with_warnings, parse_pattern, parse_pattern_steps};
pub use pattern::{Assignment, CreasePattern, PatternEdge, PatternError};
pub use sheet::{Hinge, Sheet, SheetOptions, MERGE_TOLERANCE};
pub use svg::{parse_svg, SvgImport};
