//! The FMI 3.0 `modelDescription.xml` of a model.

use crate::fmu::{attr, guid, VR_FIRST_PARAM, VR_X, VR_Y};
use crate::model::Model;
use std::fmt::Write;

/// Value reference of the independent variable `time` (FMI 3.0 requires
/// exactly one). Far above the parameters, so the input, output and
/// parameters keep the value references they have in the FMI 2.0 FMU;
/// the largest value a signed 32-bit integer holds, for hosts that read
/// value references as such.
pub const VR_TIME: u32 = 0x7fff_ffff;

/// The `modelDescription.xml` of `model` (built from the spec text
/// `json`) as an FMI 3.0 co-simulation FMU named `model_name` whose binary
/// is `binaries/x86_64-linux/<identifier>.so`. The instantiation token is
/// the FMI 2.0 FMU's GUID of the same spec. Start values are written in
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
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" generationTool="hysteron {}" variableNamingConvention="structured">"#,
        attr(model_name),
        guid(json),
        attr(&format!("hysteron model: {}", spec.describe())),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="true" providesAdjointDerivatives="false" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="false" hasEventMode="false"/>"#,
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
        r#"    <Float64 name="time" valueReference="{VR_TIME}" causality="independent" variability="continuous" description="simulation time"/>"#
    );
    let _ = writeln!(
        w,
        r#"    <Float64 name="x" valueReference="{VR_X}" causality="input" variability="continuous" start="0" description="input sample, taken at the end of each step"/>"#
    );
    let _ = writeln!(
        w,
        r#"    <Float64 name="y" valueReference="{VR_Y}" causality="output" variability="continuous" initial="calculated" description="output y = H[x]"/>"#
    );
    let values = model.operator().params();
    for (i, (name, value)) in model.names().iter().zip(values).enumerate() {
        let name = name.to_string_lossy();
        let note = if tied.iter().any(|t| *t == name) {
            " (tied: set together with the other tied parameters in one fmi3SetFloat64 call)"
        } else {
            ""
        };
        let _ = writeln!(
            w,
            r#"    <Float64 name="{}" valueReference="{}" causality="parameter" variability="tunable" initial="exact" start="{:?}" description="{}"/>"#,
            attr(&name),
            VR_FIRST_PARAM as usize + i,
            value,
            attr(&format!("parameter {name}{note}")),
        );
    }
    let _ = writeln!(w, "  </ModelVariables>");
    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, r#"    <Output valueReference="{VR_Y}"/>"#);
    let _ = writeln!(w, r#"    <InitialUnknown valueReference="{VR_Y}"/>"#);
    let _ = writeln!(w, "  </ModelStructure>");
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn description_is_fmi_3_with_time_and_every_parameter_at_its_exact_start() {
        let json = r#"{"type": "cascade", "first": {"type": "play", "r": 0.1, "y0": 0.0},
                       "second": {"type": "gain", "k": 0.30000000000000004}}"#;
        let model = Model::from_json(json).unwrap();
        let xml = model_description(&model, json, "a<b", "id");
        assert!(xml.contains(r#"fmiVersion="3.0""#));
        assert!(xml.contains(&format!(r#"instantiationToken="{}""#, guid(json))));
        assert!(xml.contains(r#"modelName="a&lt;b""#));
        assert!(xml.contains(r#"<CoSimulation modelIdentifier="id""#));
        assert!(xml.contains(r#"canSerializeFMUState="true""#));
        assert_eq!(xml.matches(r#"causality="independent""#).count(), 1);
        assert!(xml.contains(r#"<Float64 name="time" valueReference="2147483647""#));
        assert!(xml.contains(r#"name="first.play.r" valueReference="2""#));
        assert!(xml.contains(
            r#"name="second.gain.k" valueReference="4" causality="parameter" variability="tunable" initial="exact" start="0.30000000000000004""#
        ));
        assert!(xml.contains(r#"<Output valueReference="1"/>"#));
        assert!(!xml.contains("fmi2"));
    }
}
