#![no_main]

libfuzzer_sys::fuzz_target!(|bytes: &[u8]| drape::scene::fuzz::image_file(bytes));
