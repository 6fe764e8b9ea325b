//! Origami: crease-pattern importers, the triangulated sheet, built-in
//! patterns and folding.
//!
//! A pattern file (ORIPA `.cp`, FOLD `.fold`, Origami Simulator `.svg`) is read
//! into a [`CreasePattern`], cleaned into a planar graph ([`planar`]) and
//! triangulated into a [`Sheet`] whose creases are hinges; [`folding`] adds
//! the sheet to a model as paper and drives its hinges by the fold progress.

pub mod builtin;
pub mod cp;
pub mod fold;
pub mod folding;
pub mod load;
mod path_data;
pub mod pattern;
pub mod planar;
pub mod sheet;
pub mod svg;
mod unfold;

pub use builtin::{builtin, Kresling, MiuraOri, BUILTIN_NAMES};
pub use cp::parse_cp;
pub use fold::{parse_fold, to_fold_json};
pub use folding::{
    folded_state_fold, hinge_states, paper_material, paper_model, paper_simulation,
    paper_simulation_on, paper_solver_settings, FoldAngleErrors, FoldMetrics, FoldRamp, HingeState,
    Paper, PaperStiffness, WorstFacet, WorstHinge, PAPER_MAX_STRAIN, PAPER_STRETCH_COMPLIANCE,
    PAPER_VERTEX_MASS,
};
pub use load::{load_pattern, load_pattern_with_warnings, parse_pattern};
pub use pattern::{Assignment, CreasePattern, PatternEdge, PatternError};
pub use sheet::{Hinge, Sheet, SheetOptions, MERGE_TOLERANCE};
pub use svg::{parse_svg, SvgImport};
