//! Helpers to test and tune a behaviour's objective function: where it peaks, its value at a
//! point, the peak and width along one axis, and renderings over two of its variables
//! (usually course × speed) as text or, with the `png` feature, as a PNG image.
//!
//! Every helper works in domain values (degrees, m/s...), snapping to the nearest grid point,
//! and scans the whole grid, so they are meant for tests and tuning, not for the helm's loop.
//!
//! ```
//! use behaviors::testing::Probe;
//! use ivp::{couple, Domain, ZaicHdg, ZaicSpd};
//! let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
//! let hdg = ZaicHdg::new(&d, "course", 90.0, 10.0, 10.0, 50.0, 50.0, 0.0, 100.0).unwrap();
//! let spd = ZaicSpd::new(&d, "speed", 2.0, 1.5, 2.5, 70.0, 70.0).unwrap();
//! let f = couple(&hdg.extract().unwrap(), &spd.extract().unwrap()).unwrap();
//! assert_eq!(f.argmax2("course", "speed"), (90.0, 2.0));
//! // Coupled 50/50 and normalized to 0..100.
//! assert_eq!(f.value_at(&[("course", 90.0), ("speed", 2.0)]), Some(100.0));
//! let along = f.profile("course", &[("speed", 2.0)]);
//! assert_eq!(along.peak(), (90.0, 100.0));
//! // The heading side falls to 50 at 90 ± 10: (50 + 100) / 2 = 75 over 80..100.
//! assert_eq!(along.width_above(75.0), 20.0);
//! let text = f.render_text("course", "speed", 36, 8);
//! assert_eq!(text.lines().count(), 8 + 2);
//! ```

use ivp::{IvpFunction, Snap};

/// One axis of a function sampled at every grid point, the other variables held fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// The variable's values, in grid order.
    pub xs: Vec<f64>,
    /// The function's value at each (`f64::NAN` where no piece covers the point).
    pub values: Vec<f64>,
}

impl Profile {
    /// The first grid point of the highest value and that value.
    pub fn peak(&self) -> (f64, f64) {
        let mut best = 0;
        for (i, v) in self.values.iter().enumerate() {
            if *v > self.values[best] || self.values[best].is_nan() {
                best = i;
            }
        }
        (self.xs[best], self.values[best])
    }

    /// The width, in the variable's units, of the run of grid points around the peak whose
    /// values are at least `level` (0 when the peak is below it): e.g. the plateau at the
    /// peak with `level` = the peak value, or the width at half height.
    pub fn width_above(&self, level: f64) -> f64 {
        let (px, pv) = self.peak();
        if pv.is_nan() || pv < level {
            return 0.0;
        }
        let at = self.xs.iter().position(|x| *x == px).unwrap_or(0);
        let ok = |i: usize| self.values[i] >= level;
        let mut lo = at;
        while lo > 0 && ok(lo - 1) {
            lo -= 1;
        }
        let mut hi = at;
        while hi + 1 < self.values.len() && ok(hi + 1) {
            hi += 1;
        }
        self.xs[hi] - self.xs[lo]
    }
}

/// Probes on an [`IvpFunction`] (implemented for it: `use behaviors::testing::Probe`).
pub trait Probe {
    /// The domain values of the first grid point (in grid order, the first variable slowest)
    /// with the highest value, one per variable of the function's domain.
    fn argmax(&self) -> Vec<f64>;
    /// [`Probe::argmax`]'s values of two variables, e.g. `("course", "speed")`.
    fn argmax2(&self, a: &str, b: &str) -> (f64, f64);
    /// The value at the grid point nearest to the given values (a variable not named is at
    /// its lowest value); `None` where no piece covers it or for a variable not in the domain.
    fn value_at(&self, point: &[(&str, f64)]) -> Option<f64>;
    /// The values along `var` with the other variables at `fixed` (lowest value if not named).
    fn profile(&self, var: &str, fixed: &[(&str, f64)]) -> Profile;
    /// A text picture over `x` (columns) and `y` (rows, highest value at the top), each
    /// variable sampled at `cols`/`rows` evenly spaced values and every other variable at the
    /// argmax: one character per cell from ` .:-=+*#%@` (low to high, scaled from the
    /// function's minimum to its maximum; `?` where no piece covers), then an axis line and
    /// a legend.
    fn render_text(&self, x: &str, y: &str, cols: usize, rows: usize) -> String;
    /// A PNG heat map over `x` (left to right) and `y` (bottom to top), one `scale`×`scale`
    /// square per grid point, black (minimum) through red and yellow to white (maximum),
    /// written to `w`; the other variables are at the argmax.
    #[cfg(feature = "png")]
    fn render_png(
        &self,
        x: &str,
        y: &str,
        scale: u32,
        w: impl std::io::Write,
    ) -> Result<(), png::EncodingError>;
}

/// The grid indices of `point` (domain values by name), others at 0; `None` for an unknown
/// variable.
fn indices(f: &IvpFunction, point: &[(&str, f64)]) -> Option<Vec<u32>> {
    let d = f.domain();
    let mut ix = vec![0; d.len()];
    for (name, v) in point {
        let k = d.index_of(name)?;
        ix[k] = d.vars()[k].index(*v, Snap::Nearest);
    }
    Some(ix)
}

fn argmax_ix(f: &IvpFunction) -> Vec<u32> {
    let d = f.domain();
    let n = d.len();
    let mut ix = vec![0u32; n];
    let mut best: Option<(f64, Vec<u32>)> = None;
    if n == 0 {
        return ix;
    }
    loop {
        if let Some(v) = f.eval(&ix)
            && best.as_ref().is_none_or(|(b, _)| v > *b)
        {
            best = Some((v, ix.clone()));
        }
        // Odometer: the last variable fastest.
        let mut k = n;
        loop {
            if k == 0 {
                return best.map_or(vec![0; n], |(_, b)| b);
            }
            k -= 1;
            ix[k] += 1;
            if ix[k] < d.vars()[k].points() {
                break;
            }
            ix[k] = 0;
        }
    }
}

/// Grid values of a cell over `x` and `y`: `(x index, y index)` for each sample, with the
/// rest of the point from `base`.
fn sample(f: &IvpFunction, base: &[u32], kx: usize, ky: usize, ix: u32, iy: u32) -> Option<f64> {
    let mut p = base.to_vec();
    p[kx] = ix;
    p[ky] = iy;
    f.eval(&p)
}

/// The `k`-th of `count` evenly spaced grid indices over `points` grid points.
fn spread(k: usize, count: usize, points: u32) -> u32 {
    if count <= 1 || points <= 1 {
        return 0;
    }
    let top = f64::from(points - 1);
    ((k as f64) * top / ((count - 1) as f64)).round() as u32
}

impl Probe for IvpFunction {
    fn argmax(&self) -> Vec<f64> {
        let ix = argmax_ix(self);
        self.domain()
            .vars()
            .iter()
            .zip(&ix)
            .map(|(v, i)| v.value(*i))
            .collect()
    }

    fn argmax2(&self, a: &str, b: &str) -> (f64, f64) {
        let at = self.argmax();
        let d = self.domain();
        let get = |n: &str| {
            d.index_of(n)
                .map(|k| at[k])
                .unwrap_or_else(|| panic!("`{n}` is not a variable of the function ({d})"))
        };
        (get(a), get(b))
    }

    fn value_at(&self, point: &[(&str, f64)]) -> Option<f64> {
        self.eval(&indices(self, point)?)
    }

    fn profile(&self, var: &str, fixed: &[(&str, f64)]) -> Profile {
        let d = self.domain();
        let k = d
            .index_of(var)
            .unwrap_or_else(|| panic!("`{var}` is not a variable of the function ({d})"));
        let mut ix = indices(self, fixed).unwrap_or_else(|| vec![0; d.len()]);
        let v = &d.vars()[k];
        let mut xs = Vec::with_capacity(v.points() as usize);
        let mut values = Vec::with_capacity(v.points() as usize);
        for i in 0..v.points() {
            ix[k] = i;
            xs.push(v.value(i));
            values.push(self.eval(&ix).unwrap_or(f64::NAN));
        }
        Profile { xs, values }
    }

    fn render_text(&self, x: &str, y: &str, cols: usize, rows: usize) -> String {
        const SHADES: &[u8] = b" .:-=+*#%@";
        let d = self.domain();
        let (kx, ky) = (axis(self, x), axis(self, y));
        let base = argmax_ix(self);
        let (lo, hi) = (self.min_val(), self.max_val());
        let (vx, vy) = (&d.vars()[kx], &d.vars()[ky]);
        let mut out = String::new();
        for r in (0..rows).rev() {
            let iy = spread(r, rows, vy.points());
            for c in 0..cols {
                let ix = spread(c, cols, vx.points());
                let ch = match sample(self, &base, kx, ky, ix, iy) {
                    None => b'?',
                    Some(v) => {
                        let t = if hi > lo { (v - lo) / (hi - lo) } else { 1.0 };
                        let k = (t * (SHADES.len() - 1) as f64).round() as usize;
                        SHADES[k.min(SHADES.len() - 1)]
                    }
                };
                out.push(ch as char);
            }
            out.push_str(&format!(" {y}={}\n", vy.value(iy)));
        }
        out.push_str(&format!(
            "{x}: {} .. {} over {cols} columns\n",
            vx.value(0),
            vx.value(vx.points() - 1)
        ));
        out.push_str(&format!("values {lo} (' ') .. {hi} ('@')\n"));
        out
    }

    #[cfg(feature = "png")]
    fn render_png(
        &self,
        x: &str,
        y: &str,
        scale: u32,
        w: impl std::io::Write,
    ) -> Result<(), png::EncodingError> {
        let d = self.domain();
        let (kx, ky) = (axis(self, x), axis(self, y));
        let base = argmax_ix(self);
        let (lo, hi) = (self.min_val(), self.max_val());
        let (nx, ny) = (d.vars()[kx].points(), d.vars()[ky].points());
        let scale = scale.max(1);
        let (width, height) = (nx * scale, ny * scale);
        let mut data = vec![0u8; (width * height * 3) as usize];
        for py in 0..height {
            let iy = ny - 1 - py / scale;
            for px in 0..width {
                let ix = px / scale;
                let rgb = match sample(self, &base, kx, ky, ix, iy) {
                    None => [0, 0, 128],
                    Some(v) => heat(if hi > lo { (v - lo) / (hi - lo) } else { 1.0 }),
                };
                let at = ((py * width + px) * 3) as usize;
                data[at..at + 3].copy_from_slice(&rgb);
            }
        }
        let mut enc = png::Encoder::new(w, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(&data)?;
        writer.finish()
    }
}

/// Black through red and yellow to white for `t` in 0..=1.
#[cfg(feature = "png")]
fn heat(t: f64) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0) * 3.0;
    let c = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    [c(t), c(t - 1.0), c(t - 2.0)]
}

fn axis(f: &IvpFunction, name: &str) -> usize {
    let d = f.domain();
    d.index_of(name)
        .unwrap_or_else(|| panic!("`{name}` is not a variable of the function ({d})"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ivp::{Domain, ZaicPeak};

    fn speed_peak() -> IvpFunction {
        let d = Domain::parse_specs(["speed:0:4:41"]).unwrap();
        let mut z = ZaicPeak::new(&d, "speed").unwrap();
        z.set_params(2.0, 0.5, 1.0, 20.0, 0.0, 100.0).unwrap();
        z.extract().unwrap()
    }

    #[test]
    fn a_one_dimensional_peak_has_its_summit_plateau_and_base() {
        let f = speed_peak();
        assert_eq!(f.argmax(), [2.0]);
        let p = f.profile("speed", &[]);
        assert_eq!(p.peak(), (2.0, 100.0));
        // 100 at the summit 2, 80 (summit delta 20) at 2 ± 0.5, then down to 0 over the
        // base width 1.0 on each side: 40 is met from 1.0 to 3.0.
        assert_eq!(p.width_above(100.0), 0.0);
        assert_eq!(p.width_above(80.0), 1.0);
        assert_eq!(p.width_above(40.0), 2.0);
        assert_eq!(p.width_above(150.0), 0.0);
        assert_eq!(f.value_at(&[("speed", 0.2)]), Some(0.0));
        assert_eq!(f.value_at(&[("depth", 1.0)]), None);
    }
}
