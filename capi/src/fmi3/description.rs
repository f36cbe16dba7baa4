//! The FMI 3.0 `modelDescription.xml` of a model.

use super::variables::variables;
use crate::fmu::description::{
    attr, identity, parameters, structured_name, tied_note, Parameter, LOG_CATEGORIES,
    X_DESCRIPTION, Y_DESCRIPTION,
};
use crate::fmu::{Fmi, VR_X, VR_Y};
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
/// the FMI 2.0 FMU's GUID of the same spec. A vector parameter is one
/// array variable, at the value reference of its first element, whose
/// start lists its elements' values in row-major order (see
/// `fmi3::variables`). Start values are written in Rust's shortest
/// round-trip form, so they read back bit for bit.
pub fn model_description(model: &Model, json: &str, model_name: &str, identifier: &str) -> String {
    let identity = identity(model, json, model_name, "instantiationToken");
    let identifier = attr(identifier);
    let mut xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" {identity} variableNamingConvention="structured">
  <CoSimulation modelIdentifier="{identifier}" canHandleVariableCommunicationStepSize="true" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="true" providesAdjointDerivatives="false" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="false" hasEventMode="false"/>
{LOG_CATEGORIES}  <ModelVariables>
    <Float64 name="time" valueReference="{VR_TIME}" causality="independent" variability="continuous" description="simulation time"/>
    <Float64 name="x" valueReference="{VR_X}" causality="input" variability="continuous" start="0" description="{X_DESCRIPTION}"/>
    <Float64 name="y" valueReference="{VR_Y}" causality="output" variability="continuous" initial="calculated" description="{Y_DESCRIPTION}"/>
"#
    );
    let params = parameters(model, Fmi::V3);
    let names: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
    for v in variables(&names) {
        let elements = &params[v.elements.clone()];
        let start: Vec<String> = elements.iter().map(|p| format!("{:?}", p.start)).collect();
        let description = match elements {
            [p] if v.dimensions.is_empty() => p.description.clone(),
            _ => array_description(elements),
        };
        // Writing to a String cannot fail.
        let _ = write!(
            xml,
            r#"    <Float64 name="{}" valueReference="{}" causality="parameter" variability="tunable" initial="exact" start="{}" description="{}""#,
            attr(&structured_name(&v.name)),
            v.value_reference(),
            start.join(" "),
            attr(&description),
        );
        if v.dimensions.is_empty() {
            xml.push_str("/>\n");
        } else {
            xml.push_str(">\n");
            for size in &v.dimensions {
                let _ = writeln!(xml, r#"      <Dimension start="{size}"/>"#);
            }
            xml.push_str("    </Float64>\n");
        }
    }
    let _ = write!(
        xml,
        r#"  </ModelVariables>
  <ModelStructure>
    <Output valueReference="{VR_Y}"/>
    <InitialUnknown valueReference="{VR_Y}"/>
  </ModelStructure>
</fmiModelDescription>
"#
    );
    xml
}

/// The description of an array of the parameters `elements`: `parameters
/// w[0] to w[7]`, and how to set it if one of them is tied.
fn array_description(elements: &[Parameter]) -> String {
    let (first, last) = (&elements[0].name, &elements[elements.len() - 1].name);
    let tied = elements.iter().any(|p| p.tied);
    let note = if tied {
        tied_note(Fmi::V3)
    } else {
        String::new()
    };
    format!("parameters {first} to {last}{note}")
}
