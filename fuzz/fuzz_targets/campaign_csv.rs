#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| trueaxis_fuzz::campaign_csv(data));
