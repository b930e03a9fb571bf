#![no_main]
//! libFuzzer entry point; the body is [`subdiv_fuzz::end_to_end`].
libfuzzer_sys::fuzz_target!(|data: &[u8]| subdiv_fuzz::end_to_end(data));
