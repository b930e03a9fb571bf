#![no_main]
//! libFuzzer entry point; the body is [`subdiv_fuzz::usd`].
libfuzzer_sys::fuzz_target!(|data: &[u8]| subdiv_fuzz::usd(data));
