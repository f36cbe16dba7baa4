//! The FMI 2.0 `modelDescription.xml` of a model.

use crate::fmu::{attr, guid, VR_FIRST_PARAM, VR_X, VR_Y};
use crate::model::Model;
use std::fmt::Write;

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
