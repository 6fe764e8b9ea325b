//! Finding a layer order: depth-first search over the unknowns with
//! propagation after every choice. Each condition binds at most six
//! unknowns (the pairs of its four facets), so it is revised by trying
//! every completion of its open unknowns: one that only one value of an
//! unknown allows fixes it (generalised arc consistency), one that none
//! allows is a conflict and the last choice is undone.

use super::constraints::{Condition, Problem};

/// Most choices tried before the search gives up.
const MOST_CHOICES: usize = 1_000_000;

/// Why no order came out.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Unsolved {
    /// The conditions contradict each other: the first conflict met before
    /// any choice, as the facets of the condition that failed (or of the
    /// crease, for a crease fixed both ways).
    Contradiction(Vec<u32>),
    /// The search ran out of its choices.
    TooHard,
}

/// The unknowns of each condition, as (unknown, value meaning "the first
/// facet of the pair lies above the second") for each pair of its facets in
/// order (0 1, 0 2, 0 3, 1 2, 1 3, 2 3).
struct Bound {
    facets: Vec<u32>,
    literals: Vec<(usize, bool)>,
}

impl Bound {
    fn literal(&self, a: u32, b: u32) -> (usize, bool) {
        let (i, j) = (self.position(a), self.position(b));
        let (lo, hi) = (i.min(j), i.max(j));
        let n = self.facets.len();
        // Pairs before row `lo`: (n - 1) + (n - 2) + ... (lo terms).
        let k = lo * (2 * n - lo - 1) / 2 + (hi - lo - 1);
        let (var, sense) = self.literals[k];
        (var, if i < j { sense } else { !sense })
    }

    fn position(&self, f: u32) -> usize {
        self.facets
            .iter()
            .position(|&x| x == f)
            .expect("a facet of the condition")
    }
}

/// Search state.
struct Search<'a> {
    conditions: &'a [Condition],
    bound: Vec<Bound>,
    /// Per unknown, the conditions it takes part in.
    watching: Vec<Vec<u32>>,
    value: Vec<Option<bool>>,
    /// Unknowns in the order they were set.
    trail: Vec<usize>,
}

/// A layer order found.
pub(super) struct Solution {
    /// One value per unknown.
    pub(super) values: Vec<bool>,
    /// Whether the creases and conditions force it, without a choice of the
    /// search: true for the unknowns every valid order shares.
    pub(super) forced: Vec<bool>,
}

/// One value for every unknown of `problem`, or why there is none.
pub(super) fn solve(problem: &Problem) -> Result<Solution, Unsolved> {
    let mut search = Search::new(problem);
    for &(var, value) in &problem.fixed {
        if search.value[var] == Some(!value) {
            return Err(Unsolved::Contradiction(problem.pairs[var].to_vec()));
        }
        search.set(var, value);
    }
    let every: Vec<u32> = (0..problem.conditions.len() as u32).collect();
    if let Err(c) = search.propagate(every) {
        return Err(Unsolved::Contradiction(
            problem.conditions[c as usize].facets().to_vec(),
        ));
    }
    let mut forced = vec![false; problem.pairs.len()];
    for &var in &search.trail {
        forced[var] = true;
    }
    search.depth_first()?;
    Ok(Solution {
        values: search
            .value
            .into_iter()
            .map(|v| v.unwrap_or(true))
            .collect(),
        forced,
    })
}

/// Whether `values` (one per unknown, `None` where unknown) break
/// `condition`: `None` when it binds an unknown left open.
pub(super) fn breaks(
    problem: &Problem,
    condition: &Condition,
    values: &[Option<bool>],
) -> Option<bool> {
    let bound = Bound::of(problem, condition);
    if bound.literals.iter().any(|&(var, _)| values[var].is_none()) {
        return None;
    }
    Some(!condition.holds(|a, b| {
        let (var, sense) = bound.literal(a, b);
        values[var] == Some(sense)
    }))
}

impl Bound {
    fn of(problem: &Problem, condition: &Condition) -> Bound {
        let facets = condition.facets().to_vec();
        let mut literals = Vec::with_capacity(6);
        for (i, &a) in facets.iter().enumerate() {
            for &b in &facets[i + 1..] {
                literals.push(problem.literal(a, b).expect("conditions bind known pairs"));
            }
        }
        Bound { facets, literals }
    }
}

impl<'a> Search<'a> {
    fn new(problem: &'a Problem) -> Search<'a> {
        let bound: Vec<Bound> = problem
            .conditions
            .iter()
            .map(|c| Bound::of(problem, c))
            .collect();
        let mut watching = vec![Vec::new(); problem.pairs.len()];
        for (c, b) in bound.iter().enumerate() {
            for &(var, _) in &b.literals {
                if watching[var].last() != Some(&(c as u32)) {
                    watching[var].push(c as u32);
                }
            }
        }
        Search {
            conditions: &problem.conditions,
            bound,
            watching,
            value: vec![None; problem.pairs.len()],
            trail: Vec::new(),
        }
    }

    fn set(&mut self, var: usize, value: bool) {
        self.value[var] = Some(value);
        self.trail.push(var);
    }

    fn undo_to(&mut self, length: usize) {
        for var in self.trail.drain(length..) {
            self.value[var] = None;
        }
    }

    /// Revises the conditions in `queue` and every one an unknown they fix
    /// takes part in; `Err` with the condition that no value meets.
    fn propagate(&mut self, mut queue: Vec<u32>) -> Result<(), u32> {
        while let Some(c) = queue.pop() {
            for (var, value) in self.revise(c as usize).map_err(|()| c)? {
                if self.value[var].is_none() {
                    self.set(var, value);
                    queue.extend_from_slice(&self.watching[var]);
                }
            }
        }
        Ok(())
    }

    /// The unknowns condition `c` fixes now, or `Err` when it cannot hold.
    fn revise(&self, c: usize) -> Result<Vec<(usize, bool)>, ()> {
        let bound = &self.bound[c];
        let mut open: Vec<usize> = bound
            .literals
            .iter()
            .map(|&(var, _)| var)
            .filter(|&var| self.value[var].is_none())
            .collect();
        open.dedup();
        let mut allowed = vec![[false; 2]; open.len()];
        let mut any = false;
        for mask in 0..1u32 << open.len() {
            let value = |var: usize| {
                self.value[var].unwrap_or_else(|| {
                    let k = open.iter().position(|&v| v == var).expect("open");
                    mask >> k & 1 == 1
                })
            };
            let holds = self.conditions[c].holds(|a, b| {
                let (var, sense) = bound.literal(a, b);
                value(var) == sense
            });
            if holds {
                any = true;
                for (k, a) in allowed.iter_mut().enumerate() {
                    a[(mask >> k & 1) as usize] = true;
                }
            }
        }
        if !any {
            return Err(());
        }
        Ok(open
            .iter()
            .zip(&allowed)
            .filter(|(_, a)| a[0] != a[1])
            .map(|(&var, a)| (var, a[1]))
            .collect())
    }

    /// Chooses open unknowns in turn, true first, undoing a choice whose
    /// propagation conflicts and trying the other value.
    fn depth_first(&mut self) -> Result<(), Unsolved> {
        // (unknown, trail length before it, whether false was tried too)
        let mut choices: Vec<(usize, usize, bool)> = Vec::new();
        let mut cursor = 0;
        let mut tried = 0;
        loop {
            while cursor < self.value.len() && self.value[cursor].is_some() {
                cursor += 1;
            }
            if cursor == self.value.len() {
                return Ok(());
            }
            tried += 1;
            if tried > MOST_CHOICES {
                return Err(Unsolved::TooHard);
            }
            let mark = self.trail.len();
            choices.push((cursor, mark, false));
            self.set(cursor, true);
            let mut result = self.propagate(self.watching[cursor].clone());
            while result.is_err() {
                // Undo to the latest choice not yet tried both ways.
                loop {
                    let Some((var, mark, both)) = choices.pop() else {
                        return Err(Unsolved::Contradiction(Vec::new()));
                    };
                    self.undo_to(mark);
                    if !both {
                        choices.push((var, mark, true));
                        self.set(var, false);
                        cursor = 0;
                        result = self.propagate(self.watching[var].clone());
                        break;
                    }
                }
            }
        }
    }
}
