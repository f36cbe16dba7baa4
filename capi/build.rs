//! Generates the C header of the C API into OUT_DIR; the test
//! `header_is_up_to_date` compares it with the committed
//! `include/hysteron.h`.

fn main() {
    let dir = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    println!("cargo:rerun-if-changed=src/c_api.rs");
    println!("cargo:rerun-if-changed=src/status.rs");
    println!("cargo:rerun-if-changed=cbindgen.toml");
    let config = cbindgen::Config::from_file(format!("{dir}/cbindgen.toml"))
        .expect("capi/cbindgen.toml is readable");
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(format!("{dir}/src/c_api.rs"))
        .with_src(format!("{dir}/src/status.rs"))
        .generate()
        .expect("cbindgen generates the header")
        .write_to_file(format!("{out}/hysteron.h"));
}
