//! The parameters of a model as FMI 3.0 variables: a vector parameter
//! (a Prandtl-Ishlinskii bank's weights `w[0]`, `w[1]`, …, a Maxwell-slip
//! model's stiffnesses `k[i]`) is one array variable `w` of fixed size
//! (FMI 3.0 §2.4.7.2), every other parameter a scalar.
//!
//! The flat parameter vector lists an array's elements one after another
//! in row-major order, so an array variable takes the value reference of
//! its first element (`VR_FIRST_PARAM` + its index) and its values are the
//! elements at that and the following indices. Scalars keep the value
//! references of the FMI 2.0 FMU; the value references of an array's
//! other elements name no FMI 3.0 variable.
//!
//! A run of parameters `p[i]` (or `p[i][j]`, …) becomes an array when the
//! run's indices are every index of a rectangular shape, from 0, in
//! row-major order. A ragged run (the triangular grid `mu[i][j]` of a
//! Preisach model) stays scalars, as in FMI 2.0, as does an array whose
//! name would be that of another variable.

use crate::fmu::{VR_FIRST_PARAM, VR_X, VR_Y};
use std::collections::HashSet;
use std::ops::Range;

use super::description::VR_TIME;

/// A parameter variable of the FMI 3.0 FMU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    /// Its name: the parameter's path, or for an array the path of its
    /// elements without their indices (`pi_bank.w`).
    pub name: String,
    /// The size of each dimension of an array, outermost first; empty for
    /// a scalar.
    pub dimensions: Vec<usize>,
    /// The indices of its elements in the flat parameter vector.
    pub elements: Range<usize>,
}

impl Variable {
    /// Its value reference: that of its first element.
    pub fn value_reference(&self) -> u32 {
        VR_FIRST_PARAM + self.elements.start as u32
    }

    /// The flat value references of its elements, in row-major order
    /// (those of the FMI 2.0 FMU).
    pub fn element_references(&self) -> Range<u32> {
        VR_FIRST_PARAM + self.elements.start as u32..VR_FIRST_PARAM + self.elements.end as u32
    }
}

/// `name` split into its path and its trailing indices: `w[3]` is
/// (`w`, [3]), `mu[1][0]` is (`mu`, [1, 0]), `k` is (`k`, []).
fn split_indices(name: &str) -> (&str, Vec<usize>) {
    let mut path = name;
    let mut indices = Vec::new();
    while let Some(open) = path.strip_suffix(']').and_then(|p| p.rfind('[')) {
        let Ok(index) = path[open + 1..path.len() - 1].parse::<usize>() else {
            break;
        };
        indices.push(index);
        path = &path[..open];
    }
    indices.reverse();
    (path, indices)
}

/// The shape whose every index, in row-major order, is `indices`; `None`
/// if they are not all the indices of one rectangular shape from 0.
fn shape_of(indices: &[Vec<usize>]) -> Option<Vec<usize>> {
    let rank = indices.first()?.len();
    if rank == 0 {
        return None;
    }
    let shape: Vec<usize> = (0..rank)
        .map(|d| indices.iter().map(|ix| ix[d]).max().unwrap_or(0) + 1)
        .collect();
    let mut next = vec![0; rank];
    for ix in indices {
        if *ix != next {
            return None;
        }
        // The next index in row-major order.
        for d in (0..rank).rev() {
            next[d] += 1;
            if next[d] < shape[d] || d == 0 {
                break;
            }
            next[d] = 0;
        }
    }
    (next.first() == Some(&shape[0])).then_some(shape)
}

/// The FMI 3.0 variables of the parameters named `names` (the paths of
/// the flat parameter vector, in its order), in the order of their first
/// elements.
pub fn variables<S: AsRef<str>>(names: &[S]) -> Vec<Variable> {
    let split: Vec<(&str, Vec<usize>)> = names.iter().map(|n| split_indices(n.as_ref())).collect();
    // Names an array must not take: the input, output, time and every
    // parameter's own path.
    let mut taken: HashSet<&str> = ["x", "y", "time"].into_iter().collect();
    taken.extend(names.iter().map(AsRef::as_ref));
    let scalar = |i: usize| Variable {
        name: names[i].as_ref().to_string(),
        dimensions: Vec::new(),
        elements: i..i + 1,
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < split.len() {
        let (path, rank) = (split[i].0, split[i].1.len());
        // The run of parameters with the same path and as many indices.
        let end = (i..split.len())
            .find(|&j| split[j].0 != path || split[j].1.len() != rank)
            .unwrap_or(split.len());
        let run: Vec<Vec<usize>> = split[i..end].iter().map(|(_, ix)| ix.clone()).collect();
        match shape_of(&run) {
            Some(dimensions) if taken.insert(path) => out.push(Variable {
                name: path.to_string(),
                dimensions,
                elements: i..end,
            }),
            _ => out.extend((i..end).map(scalar)),
        }
        i = end;
    }
    out
}

/// The parameter variables of an instance, to find a value reference's
/// elements.
#[derive(Debug, Clone)]
pub struct Variables {
    /// In the order of their value references.
    parameters: Vec<Variable>,
}

impl Variables {
    /// The variables of the parameters named `names`.
    pub fn of<S: AsRef<str>>(names: &[S]) -> Variables {
        Variables {
            parameters: variables(names),
        }
    }

    /// The flat value references that the variable `vr` holds, in
    /// row-major order: itself for the input, the output and `time`, an
    /// array's elements for an array. A value reference of no variable is
    /// an error naming it (and, for an array's element, its array).
    pub fn elements(&self, vr: u32) -> Result<Range<u32>, String> {
        if [VR_X, VR_Y, VR_TIME].contains(&vr) {
            return Ok(vr..vr + 1);
        }
        // The variable whose elements start at or before `vr`.
        let at = self
            .parameters
            .partition_point(|v| v.value_reference() <= vr);
        match at.checked_sub(1).map(|k| &self.parameters[k]) {
            Some(v) if v.value_reference() == vr => Ok(v.element_references()),
            Some(v) if v.element_references().contains(&vr) => Err(format!(
                "value reference {vr} is an element of the array {} (value reference {}): \
                 an array's values are read and written through its own value reference",
                v.name,
                v.value_reference()
            )),
            _ => Err(format!("no Float64 variable with value reference {vr}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn indices_are_split_off_the_path() {
        assert_eq!(split_indices("pi.w[12]"), ("pi.w", vec![12]));
        assert_eq!(split_indices("mu[1][0]"), ("mu", vec![1, 0]));
        assert_eq!(split_indices("a.k"), ("a.k", vec![]));
        assert_eq!(split_indices("a[x]"), ("a[x]", vec![]));
        assert_eq!(split_indices("a[2]b"), ("a[2]b", vec![]));
    }

    #[test]
    fn vectors_become_arrays_at_their_first_elements_reference() {
        let vars = variables(&names("a0 r[0] r[1] r[2] w[0] w[1] w[2] k"));
        let got: Vec<(&str, Vec<usize>, Range<usize>)> = vars
            .iter()
            .map(|v| (v.name.as_str(), v.dimensions.clone(), v.elements.clone()))
            .collect();
        assert_eq!(
            got,
            [
                ("a0", vec![], 0..1),
                ("r", vec![3], 1..4),
                ("w", vec![3], 4..7),
                ("k", vec![], 7..8)
            ]
        );
        assert_eq!(vars[2].value_reference(), VR_FIRST_PARAM + 4);
        assert_eq!(
            vars[2].element_references(),
            VR_FIRST_PARAM + 4..VR_FIRST_PARAM + 7
        );
        // A one-element vector is an array too.
        assert_eq!(variables(&names("s.z[0]"))[0].dimensions, [1]);
    }

    #[test]
    fn a_rectangular_grid_is_one_array_and_a_ragged_one_stays_scalars() {
        let grid = variables(&names("m[0][0] m[0][1] m[0][2] m[1][0] m[1][1] m[1][2]"));
        assert_eq!(grid.len(), 1);
        assert_eq!(
            (grid[0].dimensions.clone(), grid[0].elements.clone()),
            (vec![2, 3], 0..6)
        );
        // A Preisach grid: rows of 1, 2, 3 weights.
        let tri = names("t[0] t[1] t[2] mu[0][0] mu[1][0] mu[1][1] mu[2][0] mu[2][1] mu[2][2]");
        let vars = variables(&tri);
        assert_eq!(vars[0].dimensions, [3]);
        assert_eq!(vars.len(), 1 + 6);
        assert!(vars[1..].iter().all(|v| v.dimensions.is_empty()));
        assert_eq!(vars[1].name, "mu[0][0]");
        // Out of order, or not from 0: scalars.
        for run in [
            "v[1] v[0]",
            "v[1] v[2]",
            "v[0] v[0]",
            "m[0][0] m[1][0] m[0][1] m[1][1]",
        ] {
            let vars = variables(&names(run));
            assert!(vars.iter().all(|v| v.dimensions.is_empty()), "{run}");
        }
    }

    #[test]
    fn an_array_never_takes_another_variables_name() {
        // `w` is a scalar parameter; `x` and `time` are the FMU's own.
        for run in ["w w[0] w[1]", "x[0] x[1]", "time[0]"] {
            let vars = variables(&names(run));
            assert!(vars.iter().all(|v| v.dimensions.is_empty()), "{run}");
        }
        // Two runs of one path: the first is the array.
        let vars = variables(&names("v[0] v[1] k v[0] v[1]"));
        let arrays: Vec<&str> = vars
            .iter()
            .filter(|v| !v.dimensions.is_empty())
            .map(|v| v.name.as_str())
            .collect();
        assert_eq!(arrays, ["v"]);
        assert_eq!(vars.len(), 1 + 1 + 2);
    }

    #[test]
    fn value_references_resolve_to_their_elements() {
        let vars = Variables::of(&names("a0 w[0] w[1] w[2] k"));
        let p = VR_FIRST_PARAM;
        assert_eq!(vars.elements(VR_X).unwrap(), VR_X..VR_X + 1);
        assert_eq!(vars.elements(VR_TIME).unwrap(), VR_TIME..VR_TIME + 1);
        assert_eq!(vars.elements(p).unwrap(), p..p + 1);
        assert_eq!(vars.elements(p + 1).unwrap(), p + 1..p + 4);
        assert_eq!(vars.elements(p + 4).unwrap(), p + 4..p + 5);
        let inner = vars.elements(p + 2).unwrap_err();
        assert!(inner.contains("element of the array w"), "{inner}");
        for vr in [p + 5, 99, VR_TIME - 1] {
            let err = vars.elements(vr).unwrap_err();
            assert!(err.contains("no Float64 variable"), "{vr}: {err}");
        }
    }
}
