//! The tool table in LinuxCNC's format (`T1 P1 Z0.511 D0.125 ;comment`: tool number, pocket, the
//! offsets X Y Z A B C U V W, diameter D, lathe angles I J and orientation Q), in machine units; a
//! Fanuc program's `H` and `D` numbers are looked up as tool numbers of the same table (the tool
//! offset memory). Source: LinuxCNC 2.9 manual, "Tool Table Format".

use crate::NcError;

/// Offsets of one tool, machine units, in the interpreter's axis order X Y Z A B C U V W.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    pub number: u32,
    pub offset: [f64; 9],
    pub diameter: f64,
}

/// A tool table.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ToolTable {
    pub tools: Vec<Tool>,
}

/// The letters of the offset columns, in interpreter axis order.
pub const AXIS_LETTERS: [u8; 9] = *b"XYZABCUVW";

impl ToolTable {
    /// Reads a table; an error names the file (`origin`), the line and the field.
    pub fn parse(text: &str, origin: &str) -> Result<ToolTable, NcError> {
        let mut tools: Vec<Tool> = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split(';').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let at = |message: String| NcError { file: origin.to_string(), line: i + 1, message };
            let mut tool = Tool { number: 0, offset: [0.0; 9], diameter: 0.0 };
            let mut has_number = false;
            for field in line.split_whitespace() {
                // the letter, then the number (a field that starts with any other character,
                // multi-byte ones included, is refused below)
                let mut chars = field.chars();
                let letter = chars.next().filter(char::is_ascii).map_or(b'?', |c| c.to_ascii_uppercase() as u8);
                let value: f64 = chars
                    .as_str()
                    .parse()
                    .ok()
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| at(format!("`{field}` is not a letter and a number")))?;
                match letter {
                    b'T' => {
                        if value < 0.0 || value.fract() != 0.0 {
                            return Err(at(format!("tool number `{field}` is not a whole number")));
                        }
                        tool.number = value as u32;
                        has_number = true;
                    }
                    b'P' | b'I' | b'J' | b'Q' => {}
                    b'D' => tool.diameter = value,
                    _ => match AXIS_LETTERS.iter().position(|&l| l == letter) {
                        Some(k) => tool.offset[k] = value,
                        None => return Err(at(format!("unknown field `{field}` (T P X Y Z A B C U V W D I J Q)"))),
                    },
                }
            }
            if !has_number {
                return Err(at("no tool number T".into()));
            }
            if tools.iter().any(|t| t.number == tool.number) {
                return Err(at(format!("tool T{} appears twice", tool.number)));
            }
            tools.push(tool);
        }
        Ok(ToolTable { tools })
    }

    /// The tool numbered `number`.
    pub fn get(&self, number: u32) -> Option<&Tool> {
        self.tools.iter().find(|t| t.number == number)
    }

    /// The tool numbered `number`, writable (created with zero offsets when missing).
    pub fn entry(&mut self, number: u32) -> &mut Tool {
        if let Some(k) = self.tools.iter().position(|t| t.number == number) {
            return &mut self.tools[k];
        }
        self.tools.push(Tool { number, offset: [0.0; 9], diameter: 0.0 });
        self.tools.last_mut().expect("just pushed")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linuxcnc_tool_table_lines() {
        let t = ToolTable::parse("T1 P1 D0.125000 Z+0.511000 ;1/8 end mill\n\nT7 P9 Z-1.5 X0.2 ; lathe\n", "tool.tbl").unwrap();
        assert_eq!(t.tools.len(), 2);
        assert_eq!(t.get(1).unwrap().offset[2], 0.511);
        assert_eq!(t.get(7).unwrap().offset[0], 0.2);
        assert_eq!(t.get(1).unwrap().diameter, 0.125);
        assert!(ToolTable::parse("T1 Zx\n", "t").unwrap_err().to_string().contains("t: line 1"));
        assert!(ToolTable::parse("P1 Z1\n", "t").unwrap_err().message.contains("no tool number"));
        assert!(ToolTable::parse("T1\nT1\n", "t").unwrap_err().message.contains("twice"));
        // a field that starts with a multi-byte character: once a panic, found by fuzzing
        let e = ToolTable::parse("T1 Z1\n\u{ff}T1\n", "t").unwrap_err();
        assert_eq!(e.to_string(), "t: line 2: `\u{ff}T1` is not a letter and a number");
    }
}
