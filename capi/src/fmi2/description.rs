//! `modelDescription.xml` of a model, and the GUID that ties it to the
//! spec in `resources/model.json`.

use crate::model::Model;
use std::fmt::Write;

/// Value reference of the input `x`.
pub const VR_X: u32 = 0;
/// Value reference of the output `y`.
pub const VR_Y: u32 = 1;
/// Value reference of the first parameter (parameter `i` is `VR_FIRST_PARAM + i`).
pub const VR_FIRST_PARAM: u32 = 2;

/// The GUID of a spec's JSON text: 128 bits of FNV-1a over the text and
/// the library version, written as `{8-4-4-4-12}` hex digits. The FMU
/// refuses to instantiate when `resources/model.json` does not match the
/// description's GUID.
pub fn guid(json: &str) -> String {
    let fnv = |seed: u64| {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ seed;
        for b in env!("CARGO_PKG_VERSION").bytes().chain(json.bytes()) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        h
    };
    let (a, b) = (fnv(0), fnv(0x9e37_79b9_7f4a_7c15));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// Escapes `text` for an XML attribute.
fn attr(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// The `modelDescription.xml` of `model` (built from the spec text
/// `json`) as an FMI 2.0 co-simulation FMU named `model_name` whose binary
/// is `binaries/linux64/<identifier>.so`. Start values are written in
/// Rust's shortest round-trip form, so they read back bit for bit.
pub fn model_description(model: &Model, json: &str, model_name: &str, identifier: &str) -> String {
    let spec = model.spec();
    let tied = spec.tied_params();
    let mut x = String::new();
    let w = &mut x;
    // Writing to a String cannot fail.
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="hysteron {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        attr(model_name),
        guid(json),
        attr(&format!("hysteron model: {}", spec.describe())),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="true"/>"#,
        attr(identifier)
    );
    let _ = writeln!(w, "  <LogCategories>");
    let _ = writeln!(
        w,
        r#"    <Category name="logStatusError" description="errors: bad input, parameters or calls"/>"#
    );
    let _ = writeln!(w, "  </LogCategories>");
    let _ = writeln!(w, "  <ModelVariables>");
    let _ = writeln!(
        w,
        r#"    <ScalarVariable name="x" valueReference="{VR_X}" causality="input" variability="continuous" description="input sample, taken at the end of each step"><Real start="0"/></ScalarVariable>"#
    );
    let _ = writeln!(
        w,
        r#"    <ScalarVariable name="y" valueReference="{VR_Y}" causality="output" variability="continuous" initial="calculated" description="output y = H[x]"><Real/></ScalarVariable>"#
    );
    let values = model.operator().params();
    for (i, (name, value)) in model.names().iter().zip(values).enumerate() {
        let name = name.to_string_lossy();
        let note = if tied.iter().any(|t| *t == name) {
            " (tied: set together with the other tied parameters in one fmi2SetReal call)"
        } else {
            ""
        };
        let _ = writeln!(
            w,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="parameter" variability="tunable" initial="exact" description="{}"><Real start="{:?}"/></ScalarVariable>"#,
            attr(&name),
            VR_FIRST_PARAM as usize + i,
            attr(&format!("parameter {name}{note}")),
            value
        );
    }
    let _ = writeln!(w, "  </ModelVariables>");
    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, r#"    <Outputs><Unknown index="2"/></Outputs>"#);
    let _ = writeln!(
        w,
        r#"    <InitialUnknowns><Unknown index="2"/></InitialUnknowns>"#
    );
    let _ = writeln!(w, "  </ModelStructure>");
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guid_depends_on_every_byte_and_has_the_uuid_shape() {
        let a = guid(r#"{"type": "gain", "k": 1}"#);
        let b = guid(r#"{"type": "gain", "k": 2}"#);
        assert_ne!(a, b);
        assert_eq!(a, guid(r#"{"type": "gain", "k": 1}"#));
        let parts: Vec<usize> = a
            .trim_matches(['{', '}'])
            .split('-')
            .map(str::len)
            .collect();
        assert_eq!(parts, [8, 4, 4, 4, 12], "{a}");
    }

    #[test]
    fn description_lists_every_parameter_with_its_exact_start() {
        let json = r#"{"type": "cascade", "first": {"type": "play", "r": 0.1, "y0": 0.0},
                       "second": {"type": "gain", "k": 0.30000000000000004}}"#;
        let model = Model::from_json(json).unwrap();
        let xml = model_description(&model, json, "a<b", "id");
        assert!(xml.contains(r#"modelName="a&lt;b""#));
        assert!(xml.contains(r#"name="first.play.r" valueReference="2""#));
        assert!(xml.contains(r#"name="second.gain.k" valueReference="4""#));
        assert!(xml.contains(r#"<Real start="0.30000000000000004"/>"#));
        assert!(xml.contains(&guid(json)));
    }
}
