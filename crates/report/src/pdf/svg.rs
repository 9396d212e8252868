//! The report's SVG figures drawn as PDF vector graphics and text. The figures come from the
//! plotters SVG backend, which writes a small set of elements (`rect`, `line`, `polyline`,
//! `polygon`, `circle`, `text` with `text-anchor`, a `dy` shift and `rotate(a, x, y)`; colours as
//! `#rrggbb` with an `opacity`), so that set is what is drawn here, text as real text in the
//! embedded font; any other element is refused rather than silently dropped.

use super::font::Fonts;
use crate::ReportError;
use krilla::color::rgb;
use krilla::geom::{PathBuilder, Point, Rect, Transform};
use krilla::num::NormalizedF32;
use krilla::paint::{Fill, Stroke};
use krilla::surface::Surface;

/// The size of an SVG document in its own units (`width`, `height`, or the `viewBox`).
pub fn size(svg: &str) -> Result<(f32, f32), ReportError> {
    let doc = parse(svg)?;
    let root = doc.root_element();
    let number = |name: &str| root.attribute(name).and_then(|v| v.trim_end_matches("px").parse::<f32>().ok());
    match (number("width"), number("height")) {
        (Some(w), Some(h)) if w > 0.0 && h > 0.0 => Ok((w, h)),
        _ => {
            let v: Vec<f32> = root.attribute("viewBox").unwrap_or("").split([' ', ',']).filter_map(|t| t.parse().ok()).collect();
            match v[..] {
                [_, _, w, h] if w > 0.0 && h > 0.0 => Ok((w, h)),
                _ => Err(ReportError::Input("an SVG figure has no size".into())),
            }
        }
    }
}

fn parse(svg: &str) -> Result<roxmltree::Document<'_>, ReportError> {
    let start = svg.find("<svg").unwrap_or(0);
    roxmltree::Document::parse(&svg[start..]).map_err(|e| ReportError::Input(format!("an SVG figure is not well-formed: {e}")))
}

/// Draws `svg` with its top-left corner at `(x, y)` (pt) scaled by `scale` (pt per SVG unit).
pub fn draw(surface: &mut Surface, fonts: &Fonts, svg: &str, x: f32, y: f32, scale: f32) -> Result<(), ReportError> {
    let doc = parse(svg)?;
    surface.push_transform(&Transform::from_row(scale, 0.0, 0.0, scale, x, y));
    let result = doc.root_element().descendants().skip(1).filter(|n| n.is_element()).try_for_each(|node| element(surface, fonts, &node));
    surface.pop();
    result
}

fn number(node: &roxmltree::Node, name: &str) -> f32 {
    node.attribute(name).and_then(|v| v.trim_end_matches("px").parse().ok()).unwrap_or(0.0)
}

/// `#rrggbb` (or `none` / absent: `None`).
fn colour(text: Option<&str>) -> Option<rgb::Color> {
    let t = text?.trim();
    let hex = t.strip_prefix('#')?;
    let v = u32::from_str_radix(hex, 16).ok()?;
    match hex.len() {
        6 => Some(rgb::Color::new((v >> 16) as u8, (v >> 8) as u8, v as u8)),
        3 => Some(rgb::Color::new(((v >> 8) & 0xf) as u8 * 17, ((v >> 4) & 0xf) as u8 * 17, (v & 0xf) as u8 * 17)),
        _ => None,
    }
}

fn opacity(node: &roxmltree::Node) -> NormalizedF32 {
    let o = node.attribute("opacity").and_then(|v| v.parse::<f32>().ok()).unwrap_or(1.0);
    NormalizedF32::new(o.clamp(0.0, 1.0)).unwrap_or(NormalizedF32::ONE)
}

fn points(node: &roxmltree::Node) -> Vec<(f32, f32)> {
    let v: Vec<f32> = node.attribute("points").unwrap_or("").split([' ', ',']).filter_map(|t| t.parse().ok()).collect();
    v.chunks_exact(2).map(|p| (p[0], p[1])).collect()
}

fn polyline(points: &[(f32, f32)], close: bool) -> Option<krilla::geom::Path> {
    let mut b = PathBuilder::new();
    let (first, rest) = points.split_first()?;
    b.move_to(first.0, first.1);
    for p in rest {
        b.line_to(p.0, p.1);
    }
    if close {
        b.close();
    }
    b.finish()
}

fn paint(surface: &mut Surface, node: &roxmltree::Node, path: Option<krilla::geom::Path>, filled: bool) {
    let Some(path) = path else { return };
    let alpha = opacity(node);
    let fill = if filled { colour(node.attribute("fill")) } else { None };
    let stroke = colour(node.attribute("stroke")).map(|c| Stroke {
        paint: c.into(),
        width: node.attribute("stroke-width").and_then(|v| v.parse().ok()).unwrap_or(1.0),
        opacity: alpha,
        ..Stroke::default()
    });
    surface.set_fill(fill.map(|c| Fill { paint: c.into(), opacity: alpha, rule: Default::default() }));
    surface.set_stroke(stroke);
    surface.draw_path(&path);
    surface.set_stroke(None);
}

fn element(surface: &mut Surface, fonts: &Fonts, node: &roxmltree::Node) -> Result<(), ReportError> {
    match node.tag_name().name() {
        "rect" => {
            let (x, y, w, h) = (number(node, "x"), number(node, "y"), number(node, "width"), number(node, "height"));
            let path = Rect::from_xywh(x, y, w.max(0.0), h.max(0.0)).and_then(|r| {
                let mut b = PathBuilder::new();
                b.push_rect(r);
                b.finish()
            });
            paint(surface, node, path, true);
        }
        "line" => {
            let path = polyline(&[(number(node, "x1"), number(node, "y1")), (number(node, "x2"), number(node, "y2"))], false);
            paint(surface, node, path, false);
        }
        "polyline" => paint(surface, node, polyline(&points(node), false), false),
        "polygon" => paint(surface, node, polyline(&points(node), true), true),
        "circle" => {
            let (cx, cy, r) = (number(node, "cx"), number(node, "cy"), number(node, "r"));
            // four cubic arcs, control points at 0.5523 r (the usual circle approximation)
            let k = 0.552_284_8 * r;
            let mut b = PathBuilder::new();
            b.move_to(cx + r, cy);
            b.cubic_to(cx + r, cy + k, cx + k, cy + r, cx, cy + r);
            b.cubic_to(cx - k, cy + r, cx - r, cy + k, cx - r, cy);
            b.cubic_to(cx - r, cy - k, cx - k, cy - r, cx, cy - r);
            b.cubic_to(cx + k, cy - r, cx + r, cy - k, cx + r, cy);
            b.close();
            paint(surface, node, b.finish(), true);
        }
        "text" => text(surface, fonts, node),
        "title" | "desc" | "defs" => {}
        other => return Err(ReportError::Input(format!("an SVG figure has a `{other}` element, which the PDF cannot draw"))),
    }
    Ok(())
}

fn text(surface: &mut Surface, fonts: &Fonts, node: &roxmltree::Node) {
    let content: String = node.descendants().filter(|n| n.is_text()).filter_map(|n| n.text()).collect::<String>();
    let content = content.trim();
    if content.is_empty() {
        return;
    }
    let size = node.attribute("font-size").and_then(|v| v.trim_end_matches("px").parse().ok()).unwrap_or(16.0);
    let face = fonts.face(node.attribute("font-weight") == Some("bold"));
    let (x, mut y) = (number(node, "x"), number(node, "y"));
    // the baseline shift plotters writes for the vertical anchor: top, centre, bottom
    y += match node.attribute("dy").unwrap_or("") {
        "0.76em" => 0.76 * size,
        "0.5ex" => 0.5 * face.x_height() * size,
        "-0.5ex" => -0.5 * face.x_height() * size,
        d => d.strip_suffix("em").and_then(|v| v.parse::<f32>().ok()).map_or(0.0, |v| v * size),
    };
    let width = face.width(content, size);
    let x0 = match node.attribute("text-anchor") {
        Some("middle") => x - 0.5 * width,
        Some("end") => x - width,
        _ => x,
    };
    let rotation = node.attribute("transform").and_then(|t| {
        let v: Vec<f32> = t.trim().strip_prefix("rotate(")?.strip_suffix(')')?.split([',', ' ']).filter_map(|s| s.parse().ok()).collect();
        match v[..] {
            [a, cx, cy] => Some(Transform::from_rotate_at(a, cx, cy)),
            [a] => Some(Transform::from_rotate(a)),
            _ => None,
        }
    });
    if let Some(r) = &rotation {
        surface.push_transform(r);
    }
    let colour = colour(node.attribute("fill")).unwrap_or(rgb::Color::black());
    surface.set_fill(Some(Fill { paint: colour.into(), opacity: opacity(node), rule: Default::default() }));
    surface.set_stroke(None);
    surface.draw_glyphs(Point::from_xy(x0, y), &face.glyphs(content), face.font.clone(), content, size, false);
    if rotation.is_some() {
        surface.pop();
    }
}
