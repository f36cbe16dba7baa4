//! The FMI 2.0 `modelDescription.xml` of a model.

use crate::fmu::description::{
    attr, identity, parameters, structured_name, LOG_CATEGORIES, X_DESCRIPTION, Y_DESCRIPTION,
};
use crate::fmu::{Fmi, VR_X, VR_Y};
use crate::model::Model;
use std::fmt::Write;

/// The `modelDescription.xml` of `model` (built from the spec text
/// `json`) as an FMI 2.0 co-simulation FMU named `model_name` whose binary
/// is `binaries/linux64/<identifier>.so`. Start values are written in
/// Rust's shortest round-trip form, so they read back bit for bit.
pub fn model_description(model: &Model, json: &str, model_name: &str, identifier: &str) -> String {
    let identity = identity(model, json, model_name, "guid");
    let identifier = attr(identifier);
    let mut xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" {identity} variableNamingConvention="structured" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{identifier}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="true"/>
{LOG_CATEGORIES}  <ModelVariables>
    <ScalarVariable name="x" valueReference="{VR_X}" causality="input" variability="continuous" description="{X_DESCRIPTION}"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="y" valueReference="{VR_Y}" causality="output" variability="continuous" initial="calculated" description="{Y_DESCRIPTION}"><Real/></ScalarVariable>
"#
    );
    for p in parameters(model, Fmi::V2) {
        // Writing to a String cannot fail.
        let _ = writeln!(
            xml,
            r#"    <ScalarVariable name="{}" valueReference="{}" causality="parameter" variability="tunable" initial="exact" description="{}"><Real start="{:?}"/></ScalarVariable>"#,
            attr(&structured_name(&p.name)),
            p.value_reference,
            attr(&p.description),
            p.start
        );
    }
    xml.push_str(
        r#"  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2"/></Outputs>
    <InitialUnknowns><Unknown index="2"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"#,
    );
    xml
}
