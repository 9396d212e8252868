//! LinuxCNC HAL as a source and a sink, through LinuxCNC's own `halcmd` (one process kept open,
//! `halcmd -s -k -f` reading commands from its standard input): the source reads the mapped pins or
//! signals (`getp`) every period, time-stamped by the system clock (HAL values carry no time); the
//! sink sets the thermal-offset input pins of the HAL component of `trueaxis compensate --format
//! linuxcnc-hal` (`<component>.0.thermal-<axis>`, mm), which adds them to its corrections and drives
//! LinuxCNC's external offsets (`axis.L.eoffset-counts`).
//!
//! Units: readings as the pins give them (degC unless the mapping says K), offsets in mm.

use crate::engine::{Sample, Step};
use crate::mapping::{AddressKind, Mapping};
use crate::source::{Event, Sink, Source};
use crate::{environment, input, LiveError};
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

/// A running `halcmd`.
pub struct Halcmd {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

impl Halcmd {
    /// Starts `halcmd` and checks that every name in `pins` is a pin, parameter or signal.
    pub fn start(pins: &[String]) -> Result<Halcmd, LiveError> {
        for pin in pins {
            let out = Command::new("halcmd")
                .args(["-s", "getp", pin])
                .output()
                .map_err(|e| environment(format!("halcmd (LinuxCNC) cannot be started: {e}")))?;
            if !out.status.success() {
                let text = String::from_utf8_lossy(&out.stderr).trim().to_string();
                return Err(input(format!("HAL pin `{pin}`: {}", if text.is_empty() { "not found".into() } else { text })));
            }
        }
        let mut child = Command::new("halcmd")
            .args(["-s", "-k", "-f"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| environment(format!("halcmd (LinuxCNC) cannot be started: {e}")))?;
        let stdin = child.stdin.take().expect("piped");
        let stdout = BufReader::new(child.stdout.take().expect("piped"));
        Ok(Halcmd { child, stdin, stdout })
    }

    /// Sends commands (one per line).
    pub fn send(&mut self, commands: &str) -> Result<(), LiveError> {
        self.stdin.write_all(commands.as_bytes()).and_then(|_| self.stdin.flush()).map_err(|e| environment(format!("halcmd: {e}")))
    }

    /// The values of `pins` (one `getp` each).
    pub fn get(&mut self, pins: &[String]) -> Result<Vec<String>, LiveError> {
        let commands: String = pins.iter().map(|p| format!("getp {p}\n")).collect();
        self.send(&commands)?;
        let mut out = Vec::with_capacity(pins.len());
        for pin in pins {
            let mut line = String::new();
            let n = self.stdout.read_line(&mut line).map_err(|e| environment(format!("halcmd: {e}")))?;
            if n == 0 {
                return Err(environment(format!("halcmd ended while reading `{pin}` (is LinuxCNC still running?)")));
            }
            out.push(line.trim().to_string());
        }
        Ok(out)
    }
}

impl Drop for Halcmd {
    fn drop(&mut self) {
        let _ = self.stdin.write_all(b"exit\n");
        let _ = self.child.wait();
    }
}

/// The HAL pins of the inputs, read every period.
pub struct HalSource {
    halcmd: Halcmd,
    pins: Vec<String>,
    run_pin: Option<String>,
    units: Vec<String>,
    period: Duration,
    next_at: Instant,
}

impl HalSource {
    pub fn open(inputs: &[String], mapping: &Mapping, period: Duration) -> Result<HalSource, LiveError> {
        let pins = mapping.addresses(inputs, AddressKind::Pin)?;
        let run_pin = mapping.run_address(AddressKind::Pin);
        let all: Vec<String> = pins.iter().chain(run_pin.iter()).cloned().collect();
        let units = inputs.iter().map(|n| mapping.input_of(n).map_or("degC".into(), |i| i.unit.clone())).collect();
        Ok(HalSource { halcmd: Halcmd::start(&all)?, pins, run_pin, units, period, next_at: Instant::now() })
    }
}

impl Source for HalSource {
    fn next(&mut self, timeout: Duration) -> Result<Option<Event>, LiveError> {
        let wait = self.next_at.saturating_duration_since(Instant::now());
        if wait > timeout {
            std::thread::sleep(timeout);
            return Ok(None);
        }
        std::thread::sleep(wait);
        self.next_at += self.period;
        let all: Vec<String> = self.pins.iter().chain(self.run_pin.iter()).cloned().collect();
        let values = self.halcmd.get(&all)?;
        let readings = values[..self.pins.len()]
            .iter()
            .zip(&self.units)
            .map(|(v, u)| v.parse::<f64>().map(|x| crate::mapping::to_degc(x, u)).unwrap_or(f64::NAN))
            .collect();
        let time_s = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map_or(0.0, |d| d.as_secs_f64());
        let run = self.run_pin.as_ref().map(|_| values[self.pins.len()].clone());
        Ok(Some(Event::Sample(Sample { time_s, run, readings })))
    }
}

/// The thermal-offset pins of the HAL component, per axis of the offset map.
pub struct HalSink {
    halcmd: Halcmd,
    /// (index in the engine's offsets, pin).
    pins: Vec<(usize, String)>,
}

impl HalSink {
    pub fn open(letters: &[char], mapping: &Mapping) -> Result<HalSink, LiveError> {
        let mut pins = Vec::new();
        for (k, l) in letters.iter().enumerate() {
            if let Some(pin) = mapping.output.get(&l.to_string()).and_then(|o| o.pin.clone()) {
                pins.push((k, pin));
            }
        }
        if pins.is_empty() {
            return Err(input(format!(
                "{}: the HAL sink needs a pin per axis, e.g. [output.Z] pin = \"ta-vmc3.0.thermal-z\" (the HAL component of compensate --format linuxcnc-hal)",
                mapping.origin
            )));
        }
        let names: Vec<String> = pins.iter().map(|(_, p)| p.clone()).collect();
        Ok(HalSink { halcmd: Halcmd::start(&names)?, pins })
    }
}

impl Sink for HalSink {
    fn write(&mut self, step: &Step) -> Result<(), LiveError> {
        if !step.write {
            return Ok(());
        }
        // um -> mm, the unit of LinuxCNC's linear axes
        let commands: String = self.pins.iter().map(|(k, pin)| format!("setp {pin} {:.7}\n", step.offsets_um[*k] * 1e-3)).collect();
        self.halcmd.send(&commands)
    }
}
