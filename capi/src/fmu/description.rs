//! What the FMI 2.0 and FMI 3.0 `modelDescription.xml` of a model share:
//! the model's identity on the root element, the log category, the texts
//! of the input and output, and the parameters with their value
//! references, start values and descriptions. Each version writes them in
//! its own elements ([`fmi2`](crate::fmi2), [`fmi3`](crate::fmi3)).

use super::{guid, Fmi, VR_FIRST_PARAM};
use crate::model::Model;
use std::ffi::CStr;

/// The one log category: every message the FMU logs is an error.
pub const LOG_CATEGORY: &CStr = c"logStatusError";

/// The `<LogCategories>` element (indented as a child of the root, one
/// line per tag).
pub const LOG_CATEGORIES: &str = r#"  <LogCategories>
    <Category name="logStatusError" description="errors: bad input, parameters or calls"/>
  </LogCategories>
"#;

/// The description of the input `x`.
pub const X_DESCRIPTION: &str = "input sample, taken at the end of each step";

/// The description of the output `y`.
pub const Y_DESCRIPTION: &str = "output y = H[x]";

/// The attributes of the root element that say which model this is:
/// `modelName`, the GUID of the spec `json` under the attribute `token`
/// (`guid` in FMI 2.0, `instantiationToken` in FMI 3.0), `description`
/// and `generationTool`, escaped.
pub fn identity(model: &Model, json: &str, model_name: &str, token: &str) -> String {
    format!(
        r#"modelName="{}" {token}="{}" description="{}" generationTool="hysteron {}""#,
        attr(model_name),
        guid(json),
        attr(&format!("hysteron model: {}", model.spec().describe())),
        env!("CARGO_PKG_VERSION"),
    )
}

/// A parameter of the model as the descriptions list it (the texts are
/// not escaped).
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// Its path (`left.mms.f_c`).
    pub name: String,
    /// Its value reference, `VR_FIRST_PARAM` + its index in the flat
    /// parameter vector.
    pub value_reference: u32,
    /// Its value in the spec.
    pub start: f64,
    /// Whether it is tied to others (it can only be set together with
    /// them).
    pub tied: bool,
    /// `parameter <path>`, and for a tied parameter how to set it.
    pub description: String,
}

/// How to set a tied parameter in `api`, as its description says it.
pub fn tied_note(api: Fmi) -> String {
    format!(
        " (tied: set together with the other tied parameters in one {} call)",
        api.set_real()
    )
}

/// The parameters of `model`, in the order of its flat parameter vector;
/// the note on tied parameters names the setter of `api`.
pub fn parameters(model: &Model, api: Fmi) -> Vec<Parameter> {
    let tied = model.spec().tied_params();
    let values = model.operator().params();
    model
        .names()
        .iter()
        .zip(values)
        .zip(VR_FIRST_PARAM..)
        .map(|((name, start), value_reference)| {
            let name = name.to_string_lossy().into_owned();
            let tied = tied.contains(&name);
            let note = if tied { tied_note(api) } else { String::new() };
            Parameter {
                description: format!("parameter {name}{note}"),
                name,
                value_reference,
                start,
                tied,
            }
        })
        .collect()
}

/// A parameter's path as an FMI variable name under the structured naming
/// convention, whose array subscripts are one bracket with the indices
/// separated by commas: `preisach.e[1][0]` is `preisach.e[1,0]`. Paths
/// with one index or none are their own names.
pub fn structured_name(path: &str) -> String {
    path.replace("][", ",")
}

/// Escapes `text` for an XML attribute.
pub fn attr(text: &str) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_names_put_every_index_in_one_bracket() {
        assert_eq!(
            structured_name("second.preisach.e[1][0]"),
            "second.preisach.e[1,0]"
        );
        assert_eq!(structured_name("pi.w[3]"), "pi.w[3]");
        assert_eq!(structured_name("spring.k"), "spring.k");
    }

    #[test]
    fn tied_parameters_say_how_to_set_them_in_each_version() {
        let json = include_str!("../../../examples/specs/paper.json");
        let model = Model::from_json(json).unwrap();
        let tied = model.spec().tied_params();
        assert!(!tied.is_empty());
        for api in [Fmi::V2, Fmi::V3] {
            let params = parameters(&model, api);
            assert_eq!(params.len(), model.names().len());
            for (i, p) in params.iter().enumerate() {
                assert_eq!(p.value_reference, VR_FIRST_PARAM + i as u32);
                assert_eq!(p.start.to_bits(), model.operator().params()[i].to_bits());
                assert_eq!(p.tied, tied.contains(&p.name), "{p:?}");
                let note = format!("in one {} call", api.set_real());
                assert_eq!(p.description.contains(&note), p.tied, "{p:?}");
            }
        }
    }

    #[test]
    fn the_log_category_is_the_one_described() {
        let name = LOG_CATEGORY.to_str().unwrap();
        assert!(LOG_CATEGORIES.contains(&format!(r#"<Category name="{name}""#)));
    }

    #[test]
    fn attributes_are_escaped() {
        assert_eq!(
            attr(r#"a<b & "c" 'd'>"#),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;"
        );
    }
}
