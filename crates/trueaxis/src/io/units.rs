//! Units named in table headers (`dev [mm]`, `Dev_um`, `Position (mm)`) and in vendor files, and
//! the conversion of values to the units of docs/design.md, Conventions: positions in mm and deg, errors in
//! um and urad (1 urad = 1 um/m), temperatures in degC, times in s.

use std::fmt;

/// What a unit measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    Length,
    Angle,
    Temperature,
    Time,
    /// Feed rates (ballbar exports).
    Velocity,
    /// Sample rates (ballbar exports).
    Frequency,
}

impl Dimension {
    pub fn name(self) -> &'static str {
        match self {
            Dimension::Length => "a length",
            Dimension::Angle => "an angle",
            Dimension::Temperature => "a temperature",
            Dimension::Time => "a time",
            Dimension::Velocity => "a feed rate",
            Dimension::Frequency => "a frequency",
        }
    }
}

/// A unit: its canonical symbol, dimension and the factor (and offset, for kelvin) to the base
/// unit of its dimension: mm, deg, degC, s, mm/min, Hz.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    pub symbol: &'static str,
    pub dimension: Dimension,
    factor: f64,
    offset: f64,
}

const fn unit(symbol: &'static str, dimension: Dimension, factor: f64) -> Unit {
    Unit { symbol, dimension, factor, offset: 0.0 }
}

/// Degrees per radian (180 / pi).
const DEG_PER_RAD: f64 = 57.295_779_513_082_32;

impl Unit {
    pub const MM: Unit = unit("mm", Dimension::Length, 1.0);
    pub const UM: Unit = unit("um", Dimension::Length, 1e-3);
    pub const NM: Unit = unit("nm", Dimension::Length, 1e-6);
    pub const M: Unit = unit("m", Dimension::Length, 1e3);
    pub const CM: Unit = unit("cm", Dimension::Length, 10.0);
    pub const INCH: Unit = unit("in", Dimension::Length, 25.4);
    pub const DEG: Unit = unit("deg", Dimension::Angle, 1.0);
    pub const RAD: Unit = unit("rad", Dimension::Angle, DEG_PER_RAD);
    pub const MRAD: Unit = unit("mrad", Dimension::Angle, DEG_PER_RAD * 1e-3);
    pub const URAD: Unit = unit("urad", Dimension::Angle, DEG_PER_RAD * 1e-6);
    pub const ARCSEC: Unit = unit("arcsec", Dimension::Angle, 1.0 / 3600.0);
    pub const ARCMIN: Unit = unit("arcmin", Dimension::Angle, 1.0 / 60.0);
    pub const DEGC: Unit = unit("degC", Dimension::Temperature, 1.0);
    pub const KELVIN: Unit = Unit { symbol: "K", dimension: Dimension::Temperature, factor: 1.0, offset: -273.15 };
    pub const S: Unit = unit("s", Dimension::Time, 1.0);
    pub const MS: Unit = unit("ms", Dimension::Time, 1e-3);
    pub const MIN: Unit = unit("min", Dimension::Time, 60.0);
    pub const H: Unit = unit("h", Dimension::Time, 3600.0);
    pub const MM_PER_MIN: Unit = unit("mm/min", Dimension::Velocity, 1.0);
    pub const MM_PER_S: Unit = unit("mm/s", Dimension::Velocity, 60.0);
    pub const M_PER_MIN: Unit = unit("m/min", Dimension::Velocity, 1e3);
    pub const HZ: Unit = unit("Hz", Dimension::Frequency, 1.0);
    pub const KHZ: Unit = unit("kHz", Dimension::Frequency, 1e3);

    /// Parses a unit as written in a header or a vendor file, case-insensitively where that is not
    /// ambiguous: `mm`, `um`, `µm`, `micron`, `nm`, `m`, `in`; `deg`, `°`, `rad`, `mrad`, `urad`,
    /// `µrad`, `arcsec`, `"`, `um/m` (= urad), `mm/m` (= mrad); `degC`, `°C`, `C`, `K`; `s`, `ms`,
    /// `min`, `h`; `mm/min`, `mm/s`, `m/min`; `Hz`, `kHz`. `None` for anything else.
    pub fn parse(text: &str) -> Option<Unit> {
        let key: String = text
            .trim()
            .chars()
            .filter(|c| !c.is_whitespace())
            .map(|c| match c {
                'µ' | 'μ' => 'u',
                '’' | '′' => '\'',
                '″' => '"',
                other => other,
            })
            .collect::<String>()
            .to_lowercase();
        let u = match key.as_str() {
            "mm" | "millimetre" | "millimeter" | "millimetres" | "millimeters" => Unit::MM,
            "um" | "micron" | "microns" | "micrometre" | "micrometer" | "micrometres" | "micrometers" | "mkm" => Unit::UM,
            "nm" | "nanometre" | "nanometer" | "nanometres" | "nanometers" => Unit::NM,
            "m" | "metre" | "meter" | "metres" | "meters" => Unit::M,
            "cm" => Unit::CM,
            "in" | "inch" | "inches" => Unit::INCH,
            "deg" | "°" | "degree" | "degrees" | "grad" => Unit::DEG,
            "rad" | "radian" | "radians" => Unit::RAD,
            "mrad" | "mm/m" => Unit::MRAD,
            "urad" | "um/m" | "microrad" | "microradian" | "microradians" => Unit::URAD,
            "arcsec" | "\"" | "sec" | "asec" | "arc-sec" | "arcsecond" | "arcseconds" => Unit::ARCSEC,
            "arcmin" | "'" | "arc-min" | "arcminute" | "arcminutes" => Unit::ARCMIN,
            "degc" | "°c" | "c" | "celsius" | "deg.c" => Unit::DEGC,
            "k" | "kelvin" => Unit::KELVIN,
            "s" | "sec." | "second" | "seconds" => Unit::S,
            "ms" => Unit::MS,
            "min" | "minute" | "minutes" => Unit::MIN,
            "h" | "hour" | "hours" => Unit::H,
            "mm/min" => Unit::MM_PER_MIN,
            "mm/s" => Unit::MM_PER_S,
            "m/min" => Unit::M_PER_MIN,
            "hz" | "1/s" => Unit::HZ,
            "khz" => Unit::KHZ,
            _ => return None,
        };
        Some(u)
    }

    /// The value `v` given in this unit, expressed in `to` (same dimension; checked by the caller).
    pub fn convert(self, v: f64, to: Unit) -> f64 {
        (v * self.factor + self.offset - to.offset) / to.factor
    }

    /// The factor from this unit to `to` (a value in `self` times it is the value in `to`); for
    /// differences (deviations), where the kelvin offset does not apply.
    pub fn factor_to(self, to: Unit) -> f64 {
        self.factor / to.factor
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol)
    }
}

/// The unit trueaxis uses for a quantity of `dimension` (docs/design.md, Conventions): for a *position*
/// (an axis position, a target) mm or deg, for an *error value* (a deviation, a reading) um or urad;
/// degC, s, mm/min and Hz otherwise.
pub fn canonical(dimension: Dimension, position: bool) -> Unit {
    match (dimension, position) {
        (Dimension::Length, true) => Unit::MM,
        (Dimension::Length, false) => Unit::UM,
        (Dimension::Angle, true) => Unit::DEG,
        (Dimension::Angle, false) => Unit::URAD,
        (Dimension::Temperature, _) => Unit::DEGC,
        (Dimension::Time, _) => Unit::S,
        (Dimension::Velocity, _) => Unit::MM_PER_MIN,
        (Dimension::Frequency, _) => Unit::HZ,
    }
}

/// The number at the start of `text` (decimal comma allowed, exponent allowed) and the rest of the
/// text after it, trimmed; `None` when the text does not start with a number.
pub fn leading_number(text: &str) -> Option<(f64, &str)> {
    let t = text.trim();
    let end = t
        .char_indices()
        .find(|&(i, c)| {
            let after_exponent = i > 0 && matches!(t.as_bytes()[i - 1], b'e' | b'E');
            !(c.is_ascii_digit() || c == '.' || c == ',' || ((c == '-' || c == '+') && (i == 0 || after_exponent)) || c == 'e' || c == 'E')
        })
        .map_or(t.len(), |(i, _)| i);
    // an exponent marker must be followed by digits: back off `e` of e.g. `5 edges`
    let mut number = &t[..end];
    while number.ends_with(['e', 'E', '+', '-']) {
        number = &number[..number.len() - 1];
    }
    let value = super::text::parse_number(number, true)?;
    Some((value, t[number.len()..].trim()))
}

/// A number followed by an optional unit (`1000 mm/min`, `250Hz`, `100`), as in the key-value
/// headers of vendor files. `None` when the text does not start with a number or the rest is not
/// a unit.
pub fn number_with_unit(text: &str) -> Option<(f64, Option<Unit>)> {
    let (value, rest) = leading_number(text)?;
    if rest.is_empty() {
        return Some((value, None));
    }
    Unit::parse(rest).map(|u| (value, Some(u)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_between_units_of_one_dimension() {
        assert!((Unit::MM.convert(0.0123, Unit::UM) - 12.3).abs() < 1e-12);
        assert!((Unit::DEG.convert(1.0, Unit::URAD) - 17_453.292_519_943_3).abs() < 1e-6);
        assert!((Unit::ARCSEC.convert(1.0, Unit::URAD) - 4.848_136_811_095_36).abs() < 1e-9);
        assert!((Unit::KELVIN.convert(293.15, Unit::DEGC) - 20.0).abs() < 1e-12);
        assert!((Unit::parse("um/m").unwrap().convert(3.0, Unit::URAD) - 3.0).abs() < 1e-12);
        assert_eq!(Unit::parse("µm"), Some(Unit::UM));
        assert_eq!(Unit::parse(" Deg "), Some(Unit::DEG));
        assert_eq!(Unit::parse("+"), None);
    }

    #[test]
    fn numbers_with_units() {
        assert_eq!(number_with_unit("1000 mm/min"), Some((1000.0, Some(Unit::MM_PER_MIN))));
        assert_eq!(number_with_unit("250Hz"), Some((250.0, Some(Unit::HZ))));
        assert_eq!(number_with_unit("100,5"), Some((100.5, None)));
        assert_eq!(number_with_unit("-1.5e-3 mm"), Some((-1.5e-3, Some(Unit::MM))));
        assert_eq!(number_with_unit("fast"), None);
        assert_eq!(number_with_unit("5 apples"), None);
    }
}
