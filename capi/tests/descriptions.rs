//! The `modelDescription.xml` of both FMI versions, byte for byte: each is
//! the file under `capi/testdata` with `{guid}` the GUID of its spec and
//! `{version}` the library's version, so a description changes only where
//! its file does.

use hysteron_c::{fmi2, fmi3, Model};

/// A cascade whose gain's shortest round-trip form has 17 digits.
const CASCADE: &str = r#"{"type": "cascade", "first": {"type": "play", "r": 0.1, "y0": 0.0},
    "second": {"type": "gain", "k": 0.30000000000000004}}"#;

/// Vector parameters: a PI bank's (arrays in FMI 3.0), a Preisach table's
/// inputs `x[i]` (an array too) and its triangle of weights `e[i][j]` (not
/// rectangular: scalars, as in FMI 2.0).
const VECTORS: &str = r#"{"type": "cascade",
    "first": {"type": "pi_bank", "a0": 0.5, "r": [0.0, 0.25], "w": [1.0, 0.1]},
    "second": {"type": "preisach", "start": "from_above",
               "measure": {"table": {"x": [-1, 0, 1], "e": [[0.5], [2, 0.5]]}}}}"#;

type Describe = fn(&Model, &str, &str, &str) -> String;

#[test]
fn every_description_is_its_golden_file() {
    let cases: [(&str, Describe, &str, &str); 3] = [
        (
            "fmi2-cascade",
            fmi2::model_description,
            CASCADE,
            include_str!("../testdata/fmi2-cascade.xml"),
        ),
        (
            "fmi3-cascade",
            fmi3::model_description,
            CASCADE,
            include_str!("../testdata/fmi3-cascade.xml"),
        ),
        (
            "fmi3-arrays",
            fmi3::model_description,
            VECTORS,
            include_str!("../testdata/fmi3-arrays.xml"),
        ),
    ];
    for (name, describe, json, golden) in cases {
        let model = Model::from_json(json).unwrap();
        let want = golden
            .replace("{guid}", &fmi2::guid(json))
            .replace("{version}", env!("CARGO_PKG_VERSION"));
        let got = describe(&model, json, "a<b", "id");
        assert!(got == want, "{name}: got\n{got}\nwant\n{want}");
    }
}
