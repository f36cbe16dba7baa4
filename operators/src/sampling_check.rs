//! A check every rate-independent leaf's tests share: the same input path
//! sampled more finely gives the same outputs at the shared samples.

use crate::Operator;

/// The largest `|y_coarse[i] − y_fine[m i]|` of fresh copies of `op` run
/// over `coarse` and over the same path with each increment split into `m`
/// equal ones, with the sample where it is: `(i, difference)`.
pub(crate) fn refinement_difference<O: Operator<f64> + Clone>(
    op: &O,
    coarse: &[f64],
    m: usize,
) -> (usize, f64) {
    let mut fine = Vec::with_capacity(coarse.len() * m);
    for w in coarse.windows(2) {
        if let [a, b] = w {
            fine.extend((0..m).map(|j| a + (b - a) * j as f64 / m as f64));
        }
    }
    fine.extend(coarse.last());
    let (yc, yf) = match (op.clone().run(coarse), op.clone().run(&fine)) {
        (Ok(yc), Ok(yf)) => (yc, yf),
        (Err(e), _) | (_, Err(e)) => panic!("the refinement check's runs failed: {e}"),
    };
    yc.iter()
        .zip(yf.iter().step_by(m))
        .map(|(a, b)| (a - b).abs())
        .enumerate()
        .fold(
            (0, 0.0),
            |worst, (i, d)| if d > worst.1 { (i, d) } else { worst },
        )
}
