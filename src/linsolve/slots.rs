//! The multipliers' slots of the bordered systems: a multiplier's key (where
//! its row and column meet the displacements), the slots of a new analysis,
//! a system's entries placed in its slots, and the trailing set of the
//! slots' displacements that the dense solves on the kept factor handle.

use rustc_hash::FxHashMap as HashMap;

/// Slots grouped by key: each distinct key's slots, ascending.
pub(super) struct SlotGroups {
    group_of: HashMap<SlotKey, usize>,
    groups: Vec<Vec<usize>>,
}

impl SlotGroups {
    pub(super) fn of(slots: &[SlotKey]) -> Self {
        let mut group_of: HashMap<SlotKey, usize> = HashMap::default();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for (s, key) in slots.iter().enumerate() {
            let g = *group_of.entry(key.clone()).or_insert_with(|| {
                groups.push(Vec::new());
                groups.len() - 1
            });
            groups[g].push(s);
        }
        SlotGroups { group_of, groups }
    }

    /// The slot of each key: the first slot of the same key not taken;
    /// None when a key finds none. (The grouping is made once per analysis,
    /// `Analysis::slot_groups`, not per system: hashing the capstan FMU's
    /// 230 slots took 12 us of each factorization.)
    pub(super) fn place(&self, keys: &[SlotKey]) -> Option<Vec<usize>> {
        let mut next = vec![0usize; self.groups.len()];
        keys.iter()
            .map(|k| {
                let g = *self.group_of.get(k)?;
                let s = *self.groups[g].get(next[g])?;
                next[g] += 1;
                Some(s)
            })
            .collect()
    }
}

/// Where a multiplier's row and column meet the displacement unknowns.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) struct SlotKey {
    pub(super) row: Vec<usize>,
    pub(super) column: Vec<usize>,
}

/// The slots of a new analysis for multipliers of `keys`: the kept
/// analysis's `slots` and the keys that find no free slot among them, or,
/// when those would be more than twice the keys (and 8), the keys alone.
pub(super) fn new_slots(slots: &[SlotKey], keys: &[SlotKey]) -> Vec<SlotKey> {
    let mut free: HashMap<&SlotKey, usize> = HashMap::default();
    for s in slots {
        *free.entry(s).or_default() += 1;
    }
    let mut added = Vec::new();
    for key in keys {
        match free.get_mut(key) {
            Some(c) if *c > 0 => *c -= 1,
            _ => added.push(key.clone()),
        }
    }
    if slots.len() + added.len() > 2 * keys.len() + 8 {
        return keys.to_vec();
    }
    let mut all = slots.to_vec();
    all.extend(added);
    all
}

/// The keys of the `m` multipliers (unknowns `n_disp..`) of a system given
/// by the entries `extra`; None when two multipliers are coupled.
pub(super) fn slot_keys(
    extra: &[(usize, usize, f64)],
    n_disp: usize,
    m: usize,
) -> Option<Vec<SlotKey>> {
    let mut keys = vec![
        SlotKey {
            row: Vec::new(),
            column: Vec::new(),
        };
        m
    ];
    for &(r, c, _) in extra {
        match (r >= n_disp, c >= n_disp) {
            (true, false) => keys[r - n_disp].row.push(c),
            (false, true) => keys[c - n_disp].column.push(r),
            (true, true) if r != c => return None,
            _ => {}
        }
    }
    for k in &mut keys {
        k.row.sort_unstable();
        k.row.dedup();
        k.column.sort_unstable();
        k.column.dedup();
    }
    Some(keys)
}

/// The entries `extra` with the multipliers moved to their slots, a zero
/// diagonal for each taken slot, and an empty slot's identity row (its key's
/// entries zero).
pub(super) fn in_slots(
    extra: &[(usize, usize, f64)],
    n_disp: usize,
    slots: &[SlotKey],
    slot_of: &[usize],
) -> Vec<(usize, usize, f64)> {
    let at = |i: usize| {
        if i < n_disp {
            i
        } else {
            n_disp + slot_of[i - n_disp]
        }
    };
    let mut out: Vec<(usize, usize, f64)> =
        (extra.iter()).map(|&(r, c, v)| (at(r), at(c), v)).collect();
    let mut taken = vec![false; slots.len()];
    for &s in slot_of {
        taken[s] = true;
    }
    for (s, key) in slots.iter().enumerate() {
        let i = n_disp + s;
        if taken[s] {
            out.push((i, i, 0.0));
        } else {
            out.push((i, i, 1.0));
            out.extend(key.row.iter().map(|&d| (i, d, 0.0)));
            out.extend(key.column.iter().map(|&d| (d, i, 0.0)));
        }
    }
    out
}

/// Dense work of a trailing set of `t` unknowns (about `t^3`) allowed per
/// unknown of the system: a sparse factorization of a 2D mesh costs some
/// `(nnz(L)/n)^2`, 1e3 to 1e4 flops per unknown (nnz(L)/n measured 30 to
/// 110 on the Hertz meshes of 1e3 to 1e5 unknowns), so the dense solves stay
/// well below it.
const TRAILING_FLOPS_PER_UNKNOWN: f64 = 1e4;

/// The displacement dofs the slots' rows and columns touch (the trailing
/// set with the multipliers, `trailing`) of a system of order `n` whose
/// first `n_disp` unknowns are displacements; None when there are no
/// multipliers or the set is too large for its dense solves.
pub(super) fn trailing_dofs(slots: &[SlotKey], n_disp: usize, n: usize) -> Option<Vec<usize>> {
    // The multipliers alone too many already.
    if !trailing_fits(n - n_disp, n) {
        return None;
    }
    let mut dofs: Vec<usize> = slots
        .iter()
        .flat_map(|k| k.row.iter().chain(&k.column).copied())
        .collect();
    dofs.sort_unstable();
    dofs.dedup();
    (n > n_disp && trailing_fits(dofs.len() + n - n_disp, n)).then_some(dofs)
}

/// Whether a trailing set of `t` unknowns is small enough for its dense
/// solves in a system of order `n` ([`TRAILING_FLOPS_PER_UNKNOWN`]).
pub(super) fn trailing_fits(t: usize, n: usize) -> bool {
    (t as f64).powi(3) <= TRAILING_FLOPS_PER_UNKNOWN * n as f64
}
