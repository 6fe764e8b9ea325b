//! The flat-folded geometry of a sheet: where each facet lands when every
//! crease folds to 180 degrees, which facets overlap there, and where the
//! folded creases lie.
//!
//! Facets are the sheet's triangles joined across the hinges that stay flat
//! (facet lines, auxiliary lines and the triangulation's own edges). Each
//! facet is moved by an isometry of the plane: crossing a crease reflects
//! it about the crease's line. Reached by two paths, a facet must land in
//! the same place (the creases around every vertex close: Kawasaki's
//! theorem, globally); how far apart the two landings are, over the whole
//! sheet, sets the tolerance of every later test, since patterns drawn by
//! hand close only to their drawing's round-off.

use std::collections::{HashMap, HashSet, VecDeque};

use glam::{DMat2, DVec2};

use super::super::flat_foldability::{kawasaki_defect, KAWASAKI_TOLERANCE_DEG};
use super::super::{Assignment, Hinge, PatternError, Sheet};

/// Most closure error accepted, as a fraction of the sheet's diameter: past
/// it the creases do not close and the pattern does not fold flat.
const MOST_CLOSURE_ERROR: f64 = 5e-3;

/// The tolerance is this many times the closure error...
const TOLERANCE_PER_CLOSURE_ERROR: f64 = 4.0;
/// ...and at least this fraction of the diameter (floating-point round-off).
const LEAST_TOLERANCE: f64 = 1e-5;

/// A rigid motion of the plane, reflections included: `p -> m * p + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Isometry {
    m: DMat2,
    t: DVec2,
}

impl Isometry {
    const IDENTITY: Isometry = Isometry {
        m: DMat2::IDENTITY,
        t: DVec2::ZERO,
    };

    pub(super) fn apply(&self, p: DVec2) -> DVec2 {
        self.m * p + self.t
    }

    /// True when it reverses orientation (the facet lies face down).
    pub(super) fn flips(&self) -> bool {
        self.m.determinant() < 0.0
    }

    /// This motion after the reflection about the line through `a` and `b`.
    fn after_reflection(&self, a: DVec2, b: DVec2) -> Isometry {
        let d = (b - a).normalize();
        let r = DMat2::from_cols(
            DVec2::new(d.x * d.x - d.y * d.y, 2.0 * d.x * d.y),
            DVec2::new(2.0 * d.x * d.y, d.y * d.y - d.x * d.x),
        );
        Isometry {
            m: self.m * r,
            t: self.m * (a - r * a) + self.t,
        }
    }
}

/// A crease in the folded state: the segment both its facets fold onto.
#[derive(Clone, Copy, Debug)]
pub(super) struct FoldedCrease {
    /// The facet on the `v[2]` side of the hinge, and the one on the `v[3]`
    /// side.
    pub(super) facets: [u32; 2],
    /// The segment's ends, folded.
    pub(super) ends: [DVec2; 2],
    /// A point of the facets, folded: both lie on its side of the segment.
    pub(super) inside: DVec2,
    /// Valley (true) or mountain.
    pub(super) valley: bool,
}

/// The sheet folded flat.
#[derive(Clone, Debug)]
pub(super) struct FoldedGeometry {
    /// The facet of each triangle.
    pub(super) facet_of: Vec<u32>,
    /// Each facet's motion from the flat sheet to the folded state.
    pub(super) motion: Vec<Isometry>,
    /// Each triangle folded, counter-clockwise.
    pub(super) folded: Vec<[DVec2; 3]>,
    /// For each triangle edge (`k` from corner `k` to `k + 1` of the sheet's
    /// triangle), whether it bounds its facet: a crease or the paper's edge.
    pub(super) facet_edge: Vec<[bool; 3]>,
    /// Every crease that folds.
    pub(super) creases: Vec<FoldedCrease>,
    /// Lengths closer than this are equal (metres, on the sheet).
    pub(super) tolerance: f64,
}

/// The first interior vertex of `sheet` (at `flat`) whose flat-folding
/// creases break Kawasaki's theorem by more than drawing round-off
/// ([`KAWASAKI_TOLERANCE_DEG`]), with its defect in degrees (NaN for an odd
/// number of creases). Such a vertex cannot fold flat, though the creases
/// around it may close within the closure error the sheet as a whole is
/// allowed.
fn kawasaki_failure(sheet: &Sheet, flat: &[DVec2]) -> Option<(usize, f64)> {
    let mut fan = vec![0i32; flat.len()];
    for tri in &sheet.triangles {
        for &v in tri {
            fan[v as usize] += 1;
        }
    }
    let mut creases: Vec<Vec<f64>> = vec![Vec::new(); flat.len()];
    for h in &sheet.hinges {
        let [a, b] = [h.v[0] as usize, h.v[1] as usize];
        // An interior vertex has as many edges, all hinges, as triangles.
        fan[a] -= 1;
        fan[b] -= 1;
        if let Ok(Fold::Crease { .. }) = fold_of(h, flat[a]) {
            let d = flat[b] - flat[a];
            creases[a].push(d.y.atan2(d.x));
            creases[b].push((-d.y).atan2(-d.x));
        }
    }
    creases
        .into_iter()
        .enumerate()
        .filter(|(v, directions)| fan[*v] == 0 && !directions.is_empty())
        .find_map(|(v, mut directions)| {
            directions.sort_by(f64::total_cmp);
            let by = kawasaki_defect(directions).unwrap_or(f64::NAN);
            // An odd number of creases (NaN) fails too.
            (by.is_nan() || by.abs() > KAWASAKI_TOLERANCE_DEG).then_some((v, by))
        })
}

/// What a hinge does in a flat fold.
enum Fold {
    Flat,
    Crease { valley: bool },
}

fn fold_of(hinge: &Hinge, at: DVec2) -> Result<Fold, PatternError> {
    let crease = |valley| {
        match hinge.fold_angle {
        None => Ok(Fold::Crease { valley }),
        Some(a) if a.abs() < 1e-6 => Ok(Fold::Flat),
        Some(a) if (a.abs().to_degrees() - 180.0).abs() < 1e-3 => Ok(Fold::Crease { valley }),
        Some(a) => Err(PatternError::new(
            format!("crease at ({:.4}, {:.4})", at.x, at.y),
            format!(
                "folds to {:.1} degrees, not flat: only a pattern whose creases all fold to 180 degrees has a flat-folded state",
                a.to_degrees()
            ),
        )),
    }
    };
    match hinge.assignment {
        Assignment::Valley => crease(true),
        Assignment::Mountain => crease(false),
        Assignment::Unassigned => Err(PatternError::new(
            format!("crease at ({:.4}, {:.4})", at.x, at.y),
            "is unassigned: a flat-folded state needs every crease mountain or valley",
        )),
        _ => Ok(Fold::Flat),
    }
}

impl FoldedGeometry {
    /// Folds `sheet` flat. Fails when a crease does not fold to 180
    /// degrees, when a vertex breaks Kawasaki's theorem by more than
    /// drawing round-off, or when the creases do not close (its pieces
    /// overlap inconsistently).
    pub(super) fn of(sheet: &Sheet) -> Result<FoldedGeometry, PatternError> {
        let flat: Vec<DVec2> = sheet
            .positions
            .iter()
            .map(|p| DVec2::new(p.x.into(), p.y.into()))
            .collect();
        let adjacency = Adjacency::of(sheet, &flat)?;
        if let Some((v, by)) = kawasaki_failure(sheet, &flat) {
            let at = flat[v];
            let why = if by.is_nan() {
                "an odd number of creases meets there".to_string()
            } else {
                format!(
                    "its alternate sector angles sum to {:.3} and {:.3} deg, not 180 each",
                    180.0 - by.abs(),
                    180.0 + by.abs()
                )
            };
            return Err(PatternError::new(
                format!("vertex at ({:.4}, {:.4})", at.x, at.y),
                format!("does not fold flat: Kawasaki's theorem fails there ({why})"),
            ));
        }
        let facet_of = facets(sheet.triangles.len(), &adjacency);
        let (motion, closure_error) = fold_motions(&flat, &facet_of, &adjacency)?;
        let diameter = diameter(&flat);
        if closure_error > MOST_CLOSURE_ERROR * diameter {
            return Err(PatternError::new(
                "",
                format!(
                    "does not fold flat: its creases do not close (facets reached two ways land {:.2e} of the sheet apart); Kawasaki's theorem fails somewhere",
                    closure_error / diameter
                ),
            ));
        }
        let tolerance =
            (TOLERANCE_PER_CLOSURE_ERROR * closure_error).max(LEAST_TOLERANCE * diameter);
        let folded = sheet
            .triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let m = &motion[facet_of[t] as usize];
                let p = tri.map(|v| m.apply(flat[v as usize]));
                if m.flips() {
                    [p[0], p[2], p[1]]
                } else {
                    p
                }
            })
            .collect();
        let facet_edge = sheet
            .triangles
            .iter()
            .map(|tri| {
                [0, 1, 2].map(|k| {
                    let e = edge_key(tri[k], tri[(k + 1) % 3]);
                    adjacency.crease_or_rim(e)
                })
            })
            .collect();
        let creases = adjacency
            .links
            .iter()
            .filter_map(|c| {
                let Fold::Crease { valley } = c.fold else {
                    return None;
                };
                let m = &motion[facet_of[c.triangles[0]] as usize];
                Some(FoldedCrease {
                    facets: c.triangles.map(|t| facet_of[t]),
                    ends: c.ends.map(|p| m.apply(flat[p as usize])),
                    inside: m.apply(flat[c.opposite as usize]),
                    valley,
                })
            })
            .collect();
        Ok(FoldedGeometry {
            facet_of,
            motion,
            folded,
            facet_edge,
            creases,
            tolerance,
        })
    }

    /// Number of facets.
    pub(super) fn facet_count(&self) -> usize {
        self.motion.len()
    }

    /// True when facet `f` lies face down in the folded state.
    pub(super) fn flipped(&self, f: u32) -> bool {
        self.motion[f as usize].flips()
    }
}

fn edge_key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

fn diameter(points: &[DVec2]) -> f64 {
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    (hi - lo).length().max(f64::MIN_POSITIVE)
}

/// A hinge between two triangles, as the fold sees it.
struct Link {
    triangles: [usize; 2],
    ends: [u32; 2],
    opposite: u32,
    fold: Fold,
}

/// Which triangles meet across which hinges.
struct Adjacency {
    /// Per triangle, its links (indices into `links`).
    around: Vec<Vec<usize>>,
    links: Vec<Link>,
    /// Edges that are creases or the paper's edge.
    facet_edges: HashSet<[u32; 2]>,
}

impl Adjacency {
    fn of(sheet: &Sheet, flat: &[DVec2]) -> Result<Adjacency, PatternError> {
        let mut by_edge: HashMap<[u32; 2], Vec<usize>> = HashMap::new();
        for (t, tri) in sheet.triangles.iter().enumerate() {
            for k in 0..3 {
                by_edge
                    .entry(edge_key(tri[k], tri[(k + 1) % 3]))
                    .or_default()
                    .push(t);
            }
        }
        let mut around = vec![Vec::new(); sheet.triangles.len()];
        let mut links = Vec::new();
        let mut facet_edges: HashSet<[u32; 2]> = by_edge
            .iter()
            .filter(|(_, ts)| ts.len() == 1)
            .map(|(e, _)| *e)
            .collect();
        for hinge in &sheet.hinges {
            let key = edge_key(hinge.v[0], hinge.v[1]);
            let Some(ts) = by_edge.get(&key).filter(|ts| ts.len() == 2) else {
                continue;
            };
            // The triangle holding v[2] first.
            let first = if sheet.triangles[ts[0]].contains(&hinge.v[2]) {
                0
            } else {
                1
            };
            let triangles = [ts[first], ts[1 - first]];
            let mid = (flat[hinge.v[0] as usize] + flat[hinge.v[1] as usize]) * 0.5;
            let fold = fold_of(hinge, mid)?;
            if let Fold::Crease { .. } = fold {
                facet_edges.insert(key);
            }
            let l = links.len();
            around[triangles[0]].push(l);
            around[triangles[1]].push(l);
            links.push(Link {
                triangles,
                ends: [hinge.v[0], hinge.v[1]],
                opposite: hinge.v[2],
                fold,
            });
        }
        Ok(Adjacency {
            around,
            links,
            facet_edges,
        })
    }

    fn crease_or_rim(&self, e: [u32; 2]) -> bool {
        self.facet_edges.contains(&e)
    }
}

/// Facets: triangles joined across hinges that stay flat (union-find).
fn facets(triangles: usize, adjacency: &Adjacency) -> Vec<u32> {
    let mut parent: Vec<usize> = (0..triangles).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for link in &adjacency.links {
        if let Fold::Flat = link.fold {
            let (a, b) = (
                root(&mut parent, link.triangles[0]),
                root(&mut parent, link.triangles[1]),
            );
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut number = HashMap::new();
    (0..triangles)
        .map(|t| {
            let r = root(&mut parent, t);
            let next = number.len() as u32;
            *number.entry(r).or_insert(next)
        })
        .collect()
}

/// Each facet's motion, by a breadth-first walk over the creases from the
/// first facet of each connected piece, and the largest disagreement
/// between two paths to a facet (metres).
fn fold_motions(
    flat: &[DVec2],
    facet_of: &[u32],
    adjacency: &Adjacency,
) -> Result<(Vec<Isometry>, f64), PatternError> {
    let facet_count = facet_of.iter().max().map_or(0, |&f| f as usize + 1);
    let mut motion: Vec<Option<Isometry>> = vec![None; facet_count];
    let mut closure_error: f64 = 0.0;
    for start in 0..facet_of.len() {
        if motion[facet_of[start] as usize].is_some() {
            continue;
        }
        motion[facet_of[start] as usize] = Some(Isometry::IDENTITY);
        let mut queue = VecDeque::from([start]);
        let mut seen_triangle = vec![false; facet_of.len()];
        seen_triangle[start] = true;
        while let Some(t) = queue.pop_front() {
            let here = motion[facet_of[t] as usize].expect("reached");
            for &l in &adjacency.around[t] {
                let link = &adjacency.links[l];
                let other = if link.triangles[0] == t {
                    link.triangles[1]
                } else {
                    link.triangles[0]
                };
                let there = match link.fold {
                    Fold::Flat => here,
                    Fold::Crease { .. } => here
                        .after_reflection(flat[link.ends[0] as usize], flat[link.ends[1] as usize]),
                };
                let facet = facet_of[other] as usize;
                match motion[facet] {
                    None => motion[facet] = Some(there),
                    Some(known) => {
                        for p in [link.ends[0], link.ends[1], link.opposite] {
                            let p = flat[p as usize];
                            closure_error =
                                closure_error.max((known.apply(p) - there.apply(p)).length());
                        }
                    }
                }
                if !seen_triangle[other] {
                    seen_triangle[other] = true;
                    queue.push_back(other);
                }
            }
        }
    }
    let motion = motion
        .into_iter()
        .map(|m| m.expect("every facet reached from its piece"))
        .collect();
    Ok((motion, closure_error))
}
