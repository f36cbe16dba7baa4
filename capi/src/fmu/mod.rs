//! What the FMI 2.0 and FMI 3.0 co-simulation FMUs share: the variable
//! layout, the GUID (FMI 3: instantiation token) that ties a description
//! to its spec, the instance state machine (`instance`), FMU states as
//! bytes (`serial`) and the exact directional derivatives
//! (`derivatives`); at the C boundary, the instance behind the host's
//! handle and the panic guard of every call (`component`), the host's
//! strings and arrays (`pointers`) and FMU states behind handles
//! (`states`); and what the two `modelDescription.xml` say alike
//! (`description`). The C functions around them, and the XML each
//! version writes, are in [`fmi2`](crate::fmi2) and [`fmi3`](crate::fmi3);
//! both describe the same variables under the same value references, so a
//! host moves from one to the other without renumbering.

pub(crate) mod component;
pub(crate) mod derivatives;
pub(crate) mod description;
pub(crate) mod instance;
pub(crate) mod pointers;
pub(crate) mod serial;
pub(crate) mod states;

/// The FMI version whose function and type names an instance's messages
/// use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fmi {
    /// FMI 2.0: `fmi2DoStep`, `fmi2SetReal`, Real variables.
    V2,
    /// FMI 3.0: `fmi3DoStep`, `fmi3SetFloat64`, Float64 variables.
    V3,
}

impl Fmi {
    /// The C name of the function `name` (`DoStep` → `fmi3DoStep`).
    pub fn function(self, name: &str) -> String {
        match self {
            Fmi::V2 => format!("fmi2{name}"),
            Fmi::V3 => format!("fmi3{name}"),
        }
    }

    /// The type of the FMU's variables: `Real` or `Float64`.
    pub fn real(self) -> &'static str {
        match self {
            Fmi::V2 => "Real",
            Fmi::V3 => "Float64",
        }
    }

    /// The function that sets them: `fmi2SetReal` or `fmi3SetFloat64`.
    pub fn set_real(self) -> String {
        self.function(&format!("Set{}", self.real()))
    }

    /// How the version spells an FMU state in its names: `FMUstate`
    /// (`fmi2GetFMUstate`) or `FMUState` (`fmi3GetFMUState`).
    pub fn fmu_state(self) -> &'static str {
        match self {
            Fmi::V2 => "FMUstate",
            Fmi::V3 => "FMUState",
        }
    }
}

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
    fn names_follow_the_version() {
        assert_eq!(Fmi::V2.function("DoStep"), "fmi2DoStep");
        assert_eq!(Fmi::V3.set_real(), "fmi3SetFloat64");
        assert_eq!(Fmi::V2.set_real(), "fmi2SetReal");
        let size = |api: Fmi| api.function(&format!("Serialized{}Size", api.fmu_state()));
        assert_eq!(size(Fmi::V2), "fmi2SerializedFMUstateSize");
        assert_eq!(size(Fmi::V3), "fmi3SerializedFMUStateSize");
    }
}
