//! The embedded typeface of the PDF: Liberation Sans regular and bold (SIL Open Font License 1.1,
//! `crates/report/fonts/LICENSE-OFL.txt`), metric-compatible with Arial. Text is measured and
//! placed glyph by glyph from the font's own advance widths (no kerning), so that what the layout
//! measures is exactly what the page shows.

use krilla::text::{Font, GlyphId, KrillaGlyph};
use skrifa::instance::{LocationRef, Size};
use skrifa::raw::TableProvider;
use skrifa::{FontRef, MetadataProvider};

const REGULAR: &[u8] = include_bytes!("../../fonts/LiberationSans-Regular.ttf");
const BOLD: &[u8] = include_bytes!("../../fonts/LiberationSans-Bold.ttf");

/// One face: the PDF font and the advance widths of the characters it maps (font units).
pub struct Face {
    pub font: Font,
    data: &'static [u8],
    units_per_em: f32,
}

/// The regular and the bold face.
pub struct Fonts {
    pub regular: Face,
    pub bold: Face,
}

impl Fonts {
    pub fn load() -> Option<Fonts> {
        Some(Fonts { regular: Face::new(REGULAR)?, bold: Face::new(BOLD)? })
    }

    pub fn face(&self, bold: bool) -> &Face {
        if bold {
            &self.bold
        } else {
            &self.regular
        }
    }
}

impl Face {
    fn new(data: &'static [u8]) -> Option<Face> {
        let font = Font::new(data.to_vec().into(), 0)?;
        let units_per_em = f32::from(FontRef::new(data).ok()?.head().ok()?.units_per_em());
        Some(Face { font, data, units_per_em })
    }

    fn font_ref(&self) -> FontRef<'static> {
        FontRef::new(self.data).expect("the embedded font parsed when loaded")
    }

    /// Glyph and advance (em) of each character; characters the font lacks take its `.notdef`.
    fn glyphs_of(&self, text: &str) -> Vec<(u32, f32, std::ops::Range<usize>)> {
        let font = self.font_ref();
        let charmap = font.charmap();
        let metrics = font.glyph_metrics(Size::unscaled(), LocationRef::default());
        text.char_indices()
            .map(|(i, c)| {
                let gid = charmap.map(c).unwrap_or_default();
                let advance = metrics.advance_width(gid).unwrap_or(0.0) / self.units_per_em;
                (gid.to_u32(), advance, i..i + c.len_utf8())
            })
            .collect()
    }

    /// Width of `text` at `size` (pt).
    pub fn width(&self, text: &str, size: f32) -> f32 {
        self.glyphs_of(text).iter().map(|g| g.1).sum::<f32>() * size
    }

    /// The glyphs of `text` as krilla places them (advances in em).
    pub fn glyphs(&self, text: &str) -> Vec<KrillaGlyph> {
        self.glyphs_of(text)
            .into_iter()
            .map(|(gid, advance, range)| KrillaGlyph::new(GlyphId::new(gid), advance, 0.0, 0.0, 0.0, range, None))
            .collect()
    }

    /// Height of the lower-case x above the baseline, em.
    pub fn x_height(&self) -> f32 {
        let m = self.font_ref().metrics(Size::unscaled(), LocationRef::default());
        m.x_height.map_or(0.52, |h| h / self.units_per_em)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_are_the_font_advances() {
        let fonts = Fonts::load().unwrap();
        // Liberation Sans is metric-compatible with Arial: "0" is 1139 / 2048 em wide, a space 569
        let zero = fonts.regular.width("0", 10.0);
        assert!((zero - 10.0 * 1139.0 / 2048.0).abs() < 1e-3, "{zero}");
        assert!((fonts.regular.width("00 0", 10.0) - (3.0 * 1139.0 + 569.0) / 204.8).abs() < 1e-3);
        assert!(fonts.bold.width("W", 10.0) > fonts.regular.width("i", 10.0));
        for c in ['±', 'µ', '°', '≤', '−'] {
            assert!(fonts.regular.glyphs(&c.to_string())[0].glyph_id != GlyphId::new(0), "{c} is in the font");
        }
    }
}
