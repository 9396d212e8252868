//! Traceability of a report: the input files it was made from (size and SHA-256, so that a customer
//! can check that a file in hand is the one the numbers come from), the date and the software version.

use super::super::html::Section;
use std::path::Path;
use trueaxis::data::DataError;

/// One input file of a report.
#[derive(Clone, Debug, PartialEq)]
pub struct InputFile {
    /// What the file is (`machine`, `campaign data`, `ballbar circle`).
    pub role: String,
    /// The path as given (or the name in an output folder).
    pub path: String,
    pub bytes: u64,
    /// SHA-256 of the contents (FIPS 180-4), lower-case hexadecimal: what `sha256sum FILE` prints.
    pub sha256: String,
    /// What a data file records about its test (machine, serial number, date, operator, axis,
    /// environment: `trueaxis::io::Metadata`), one item per entry; empty for other files.
    pub recorded: Vec<String>,
    /// The same, as read (`None` for a file that is not a data file).
    pub metadata: Option<trueaxis::io::Metadata>,
}

impl InputFile {
    /// The file at `path`, read to hash it.
    pub fn read(role: &str, path: &Path) -> Result<InputFile, DataError> {
        let bytes = trueaxis::files::inputs::read(path).map_err(|source| DataError::Read { path: path.display().to_string(), source })?;
        Ok(InputFile::of_bytes(role, &path.display().to_string(), &bytes))
    }

    pub fn of_bytes(role: &str, path: &str, bytes: &[u8]) -> InputFile {
        let metadata = recorded(path, bytes);
        InputFile {
            role: role.into(),
            path: path.into(),
            bytes: bytes.len() as u64,
            sha256: hex(&sha256(bytes)),
            recorded: metadata.as_ref().map(|m| m.lines()).unwrap_or_default(),
            metadata,
        }
    }
}

/// What a report was made from, and when and with what.
#[derive(Clone, Debug, PartialEq)]
pub struct Traceability {
    pub inputs: Vec<InputFile>,
    /// `YYYY-MM-DD hh:mm UTC`.
    pub date: String,
    /// `trueaxis x.y.z`.
    pub software: String,
    /// The command that made the report, when made from the command line.
    pub command: Option<String>,
}

impl Traceability {
    /// Now (or `SOURCE_DATE_EPOCH` when set, the reproducible-builds convention), this version.
    pub fn now(inputs: Vec<InputFile>, command: Option<String>) -> Traceability {
        let seconds = std::env::var("SOURCE_DATE_EPOCH")
            .ok()
            .and_then(|s| s.trim().parse::<i64>().ok())
            .unwrap_or_else(|| std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64));
        Traceability { inputs, date: utc_date_time(seconds), software: format!("trueaxis {}", env!("CARGO_PKG_VERSION")), command }
    }

    /// The section listing the inputs.
    pub fn section(&self) -> Section {
        let rows = self
            .inputs
            .iter()
            .map(|f| vec![f.role.clone(), f.path.clone(), f.bytes.to_string(), f.sha256.clone(), f.recorded.join("; ")])
            .collect();
        let mut s = Section::new("inputs", "Inputs and traceability").paragraph(format!(
            "This file was written on {} by {} from the files below (the date of issue is the certificate's); `sha256sum FILE` prints the same SHA-256 for an unchanged file.",
            self.date, self.software
        ));
        if let Some(c) = &self.command {
            s = s.paragraph("Command:").code(c.clone());
        }
        s.table("Input files", &["role", "file", "bytes", "SHA-256", "recorded in the file"], rows)
    }
}

/// `YYYY-MM-DD hh:mm UTC` of a Unix time (s): the proleptic Gregorian calendar from the day count
/// (`trueaxis::io::calendar`).
pub fn utc_date_time(unix_seconds: i64) -> String {
    let second_of_day = unix_seconds.rem_euclid(86_400);
    let (year, month, day) = trueaxis::io::calendar::civil_from_days(unix_seconds.div_euclid(86_400));
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", second_of_day / 3600, second_of_day % 3600 / 60)
}

/// The metadata of a data file (a table, a Renishaw `.rtl`, a ballbar export: extensions csv, tsv,
/// txt, rtl); nothing for other files or a file that cannot be read as a table.
fn recorded(path: &str, bytes: &[u8]) -> Option<trueaxis::io::Metadata> {
    let data = Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ["csv", "tsv", "txt", "rtl"].contains(&e.to_ascii_lowercase().as_str()));
    if !data {
        return None;
    }
    trueaxis::io::text_of(bytes.to_vec(), path)
        .ok()
        .and_then(|text| trueaxis::data::CsvTable::from_text(&text, path).ok())
        .map(|t| t.metadata().clone())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Round constants of SHA-256 (FIPS 180-4 §4.2.2).
const K: [u32; 64] = [
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be,
    0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa,
    0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85,
    0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3,
    0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f,
    0x682e6ff3, 0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2,
];

/// SHA-256 of `data` (FIPS 180-4 §6.2): padding to 512-bit blocks, message schedule, 64 rounds.
pub fn sha256(data: &[u8]) -> [u8; 32] {
    let mut h: [u32; 8] = [0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19];
    let mut message = data.to_vec();
    message.push(0x80);
    while message.len() % 64 != 56 {
        message.push(0);
    }
    message.extend_from_slice(&((data.len() as u64).wrapping_mul(8)).to_be_bytes());
    for block in message.chunks_exact(64) {
        let mut w = [0u32; 64];
        for (t, word) in block.chunks_exact(4).enumerate() {
            w[t] = u32::from_be_bytes([word[0], word[1], word[2], word[3]]);
        }
        for t in 16..64 {
            let s0 = w[t - 15].rotate_right(7) ^ w[t - 15].rotate_right(18) ^ (w[t - 15] >> 3);
            let s1 = w[t - 2].rotate_right(17) ^ w[t - 2].rotate_right(19) ^ (w[t - 2] >> 10);
            w[t] = w[t - 16].wrapping_add(s0).wrapping_add(w[t - 7]).wrapping_add(s1);
        }
        let [mut a, mut b, mut c, mut d, mut e, mut f, mut g, mut hh] = h;
        for t in 0..64 {
            let s1 = e.rotate_right(6) ^ e.rotate_right(11) ^ e.rotate_right(25);
            let ch = (e & f) ^ (!e & g);
            let t1 = hh.wrapping_add(s1).wrapping_add(ch).wrapping_add(K[t]).wrapping_add(w[t]);
            let s0 = a.rotate_right(2) ^ a.rotate_right(13) ^ a.rotate_right(22);
            let maj = (a & b) ^ (a & c) ^ (b & c);
            let t2 = s0.wrapping_add(maj);
            (hh, g, f, e, d, c, b, a) = (g, f, e, d.wrapping_add(t1), c, b, a, t1.wrapping_add(t2));
        }
        for (x, y) in h.iter_mut().zip([a, b, c, d, e, f, g, hh]) {
            *x = x.wrapping_add(y);
        }
    }
    let mut out = [0u8; 32];
    for (chunk, word) in out.chunks_exact_mut(4).zip(h) {
        chunk.copy_from_slice(&word.to_be_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_matches_the_fips_180_examples() {
        // FIPS 180-4 / NIST CSRC example values: "abc", the empty message, the two-block message
        assert_eq!(hex(&sha256(b"abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
        assert_eq!(hex(&sha256(b"")), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
        assert_eq!(
            hex(&sha256(b"abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1"
        );
        // a length of 55 (padding in the same block) and 56 bytes (padding spills into a second)
        assert_eq!(hex(&sha256(&[b'a'; 55])), "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
        assert_eq!(hex(&sha256(&[b'a'; 56])), "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
    }

    #[test]
    fn utc_dates_of_known_instants() {
        assert_eq!(utc_date_time(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc_date_time(951_782_400), "2000-02-29 00:00 UTC"); // leap day of a century leap year
        assert_eq!(utc_date_time(1_700_000_000), "2023-11-14 22:13 UTC");
        assert_eq!(utc_date_time(-1), "1969-12-31 23:59 UTC");
    }
}
