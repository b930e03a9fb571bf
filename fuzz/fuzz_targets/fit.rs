#![no_main]
//! libFuzzer entry point; the body is [`subdiv_fuzz::fit`].
libfuzzer_sys::fuzz_target!(|data: &[u8]| subdiv_fuzz::fit(data));
