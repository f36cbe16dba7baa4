//! hysteron from C and from FMI 2.0 and FMI 3.0 co-simulation hosts.
//!
//! The crate builds `libhysteron_c.so`, which is two things at once:
//!
//! * **the C API** ([`c_api`], header `capi/include/hysteron.h` generated
//!   by cbindgen): a model from JSON text, `hysteron_step`,
//!   `hysteron_trial`/`hysteron_commit`, `hysteron_process`,
//!   `hysteron_reset`, parameters by name, clone and free; status codes
//!   plus `hysteron_last_error()`;
//! * **the FMU binary** ([`fmi2`], [`fmi3`]): the `fmi2*` functions of
//!   FMI 2.0 co-simulation and the `fmi3*` functions of FMI 3.0
//!   co-simulation, around one instance state machine ([`fmu`]), which
//!   `hysteron export-fmu [--fmi 3]` packs with a model's spec and its
//!   `modelDescription.xml`.
//!
//! No Rust panic crosses the C boundary: every exported function runs
//! under `catch_unwind` and reports a panic as an error (a bug).

pub mod c_api;
pub mod fmi2;
pub mod fmi3;
pub mod fmu;
pub mod model;
pub mod status;

pub use c_api::HysteronModel;
pub use model::Model;
pub use status::HysteronStatus;

#[cfg(test)]
mod tests {
    /// The committed header is the one cbindgen generates from the code.
    #[test]
    fn header_is_up_to_date() {
        let generated = include_str!(concat!(env!("OUT_DIR"), "/hysteron.h"));
        let committed = include_str!("../include/hysteron.h");
        assert!(
            generated == committed,
            "capi/include/hysteron.h is out of date: copy {}/hysteron.h over it",
            env!("OUT_DIR")
        );
    }
}
