#![no_main]
//! libFuzzer entry point; the body is [`subdiv_fuzz::project`].
libfuzzer_sys::fuzz_target!(|data: &[u8]| subdiv_fuzz::project(data));
