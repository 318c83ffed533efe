//! SVG output.

use std::fmt::Write as _;

use super::{Anchor, Canvas, PlotData, PlotError, PlotOptions, Rgba, draw, image_size};

struct Svg {
    out: String,
}

fn color(c: Rgba) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn escape(s: &str, out: &mut String) {
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
}

impl Svg {
    fn points(&mut self, pts: &[(f64, f64)]) {
        for (i, (x, y)) in pts.iter().enumerate() {
            if i > 0 {
                self.out.push(' ');
            }
            let _ = write!(self.out, "{x:.1},{y:.1}");
        }
    }
}

impl Canvas for Svg {
    fn polyline(&mut self, pts: &[(f64, f64)], c: Rgba, width: f64) {
        if pts.len() < 2 {
            return;
        }
        self.out.push_str("<polyline points=\"");
        self.points(pts);
        let _ = writeln!(
            self.out,
            "\" fill=\"none\" stroke=\"{}\" stroke-width=\"{width}\" stroke-linejoin=\"round\"/>",
            color(c)
        );
    }

    fn polygon(&mut self, pts: &[(f64, f64)], stroke: Rgba, fill: Rgba, width: f64) {
        if pts.len() < 2 {
            return;
        }
        self.out.push_str("<polygon points=\"");
        self.points(pts);
        let _ = writeln!(
            self.out,
            "\" fill=\"{}\" fill-opacity=\"{}\" stroke=\"{}\" stroke-width=\"{width}\"/>",
            color(fill),
            fill.3,
            color(stroke)
        );
    }

    fn circle(&mut self, x: f64, y: f64, r: f64, fill: Rgba) {
        let _ = writeln!(
            self.out,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{r}\" fill=\"{}\"/>",
            color(fill)
        );
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, stroke: Rgba) {
        let _ = writeln!(
            self.out,
            "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"none\" stroke=\"{}\"/>",
            color(stroke)
        );
    }

    fn text(&mut self, x: f64, y: f64, text: &str, size: f64, anchor: Anchor) {
        let a = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let _ = write!(
            self.out,
            "<text x=\"{x:.1}\" y=\"{y:.1}\" font-family=\"sans-serif\" font-size=\"{:.0}\" text-anchor=\"{a}\">",
            size * 1.4
        );
        escape(text, &mut self.out);
        self.out.push_str("</text>\n");
    }
}

/// The plot as an SVG document.
pub fn to_svg(data: &PlotData, opts: &PlotOptions) -> Result<String, PlotError> {
    let (w, h) = image_size(data, opts);
    let mut s = Svg {
        out: String::with_capacity(64 * 1024),
    };
    let _ = writeln!(
        s.out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">"
    );
    let _ = writeln!(s.out, "<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>");
    draw(data, opts, &mut s)?;
    s.out.push_str("</svg>\n");
    Ok(s.out)
}
