//! PNG output, drawn with tiny-skia; text uses the built-in bitmap font.

use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

use super::font::{ADVANCE, HEIGHT, glyph};
use super::{Anchor, BLACK, Canvas, PlotData, PlotError, PlotOptions, Rgba, draw, image_size};

struct Png {
    pix: Pixmap,
}

fn paint(c: Rgba) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(Color::from_rgba8(
        c.0,
        c.1,
        c.2,
        (c.3 * 255.0).round() as u8,
    ));
    p.anti_alias = true;
    p
}

fn path(pts: &[(f64, f64)], close: bool) -> Option<tiny_skia::Path> {
    let mut pb = PathBuilder::new();
    let (x, y) = pts.first()?;
    pb.move_to(*x as f32, *y as f32);
    for (x, y) in &pts[1..] {
        pb.line_to(*x as f32, *y as f32);
    }
    if close {
        pb.close();
    }
    pb.finish()
}

fn stroke(width: f64) -> Stroke {
    Stroke {
        width: width as f32,
        line_join: tiny_skia::LineJoin::Round,
        ..Stroke::default()
    }
}

impl Canvas for Png {
    fn polyline(&mut self, pts: &[(f64, f64)], c: Rgba, width: f64) {
        if let Some(p) = path(pts, false) {
            self.pix
                .stroke_path(&p, &paint(c), &stroke(width), Transform::identity(), None);
        }
    }

    fn polygon(&mut self, pts: &[(f64, f64)], s: Rgba, fill: Rgba, width: f64) {
        if let Some(p) = path(pts, true) {
            self.pix.fill_path(
                &p,
                &paint(fill),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
            self.pix
                .stroke_path(&p, &paint(s), &stroke(width), Transform::identity(), None);
        }
    }

    fn circle(&mut self, x: f64, y: f64, r: f64, fill: Rgba) {
        if let Some(p) = PathBuilder::from_circle(x as f32, y as f32, r as f32) {
            self.pix.fill_path(
                &p,
                &paint(fill),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, s: Rgba) {
        if let Some(r) = Rect::from_xywh(x as f32, y as f32, w as f32, h as f32) {
            let p = PathBuilder::from_rect(r);
            self.pix
                .stroke_path(&p, &paint(s), &stroke(1.0), Transform::identity(), None);
        }
    }

    fn text(&mut self, x: f64, y: f64, text: &str, size: f64, anchor: Anchor) {
        let scale = (size / HEIGHT).round().max(1.0);
        let width = text.chars().count() as f64 * ADVANCE * scale - scale;
        let left = match anchor {
            Anchor::Start => x,
            Anchor::Middle => x - width / 2.0,
            Anchor::End => x - width,
        }
        .round();
        let top = (y - HEIGHT * scale).round();
        let p = paint(BLACK);
        for (i, ch) in text.chars().enumerate() {
            let Some(g) = glyph(ch) else { continue };
            let cx = left + i as f64 * ADVANCE * scale;
            for (row, bits) in g.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0b10000 >> col) != 0
                        && let Some(r) = Rect::from_xywh(
                            (cx + f64::from(col) * scale) as f32,
                            (top + row as f64 * scale) as f32,
                            scale as f32,
                            scale as f32,
                        )
                    {
                        self.pix.fill_rect(r, &p, Transform::identity(), None);
                    }
                }
            }
        }
    }
}

/// The plot as PNG bytes.
pub fn to_png(data: &PlotData, opts: &PlotOptions) -> Result<Vec<u8>, PlotError> {
    let (w, h) = image_size(data, opts);
    if w > 8000 || h > 8000 {
        return Err(PlotError::Size(w, h));
    }
    let mut pix = Pixmap::new(w, h).ok_or(PlotError::Size(w, h))?;
    pix.fill(Color::WHITE);
    let mut c = Png { pix };
    draw(data, opts, &mut c)?;
    c.pix
        .encode_png()
        .map_err(|e| PlotError::Encode(e.to_string()))
}
