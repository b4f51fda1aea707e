#![no_main]

libfuzzer_sys::fuzz_target!(|bytes: &[u8]| drape::scene::fuzz::gltf_file(bytes));
