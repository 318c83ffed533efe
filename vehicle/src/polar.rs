//! Wind and the sailing polar of uSimMarineV22 (MOOS-IvP a2a9b716 `lib_polar`): with both a
//! wind (`wind_conditions`) and a polar plot (`polar_plot`) the simulated speed is capped at
//! `polar % (at the heading relative to the wind) × wind speed`.

/// The wind: a direction the wind comes from (degrees, `[0, 360)`) and a speed (m/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wind {
    /// Direction, degrees.
    pub dir_deg: f64,
    /// Speed, m/s (>= 0).
    pub speed_mps: f64,
}

impl Wind {
    /// Applies `spd=<m/s>,dir=<deg>` (either or both) to `current`, as `WindModel::setConditions`:
    /// `None` for an unknown key, a non-number, a negative direction or a negative speed.
    ///
    /// ```
    /// use vehicle::polar::Wind;
    /// let w = Wind::parse("spd=5, dir=450", None).unwrap();
    /// assert_eq!((w.speed_mps, w.dir_deg), (5.0, 90.0));
    /// assert!(Wind::parse("gust=3", None).is_none());
    /// ```
    pub fn parse(spec: &str, current: Option<Wind>) -> Option<Wind> {
        let mut w = current;
        Wind::apply(spec, &mut w).then_some(w).flatten()
    }

    /// Applies `spd=<m/s>,dir=<deg>` to `wind` piece by piece, as `WindModel::setConditions`:
    /// a number `spd` >= 0 or `dir` >= 0 is taken (the wind becomes set); a negative `spd` is
    /// skipped; anything else stops there and gives `false`, the pieces before it staying
    /// applied. Returns `true` when every piece was read (the wind is then set).
    ///
    /// ```
    /// use vehicle::polar::Wind;
    /// let mut w = None;
    /// assert!(!Wind::apply("spd=5,gust=3", &mut w));
    /// assert_eq!(w.unwrap().speed_mps, 5.0, "the speed before the bad piece stays");
    /// ```
    pub fn apply(spec: &str, wind: &mut Option<Wind>) -> bool {
        for part in spec.split(',') {
            let (k, v) = part.split_once('=').unwrap_or((part, ""));
            let d = crate::config::parse_number(v);
            match (k.trim(), d) {
                ("spd", Some(d)) => {
                    if d >= 0.0 {
                        wind.get_or_insert_default().speed_mps = d;
                    }
                }
                ("dir", Some(d)) if d >= 0.0 => {
                    wind.get_or_insert_default().dir_deg = crate::angle::angle360(d)
                }
                _ => return false,
            }
        }
        wind.get_or_insert_default();
        true
    }

    /// The `VIEW_ARROW` uSimMarineV22 posts for this wind (MOOS `WindModel::getArrowSpec`):
    /// an arrow at the origin pointing where the wind blows to, drawn green.
    ///
    /// ```
    /// use vehicle::polar::Wind;
    /// let w = Wind { dir_deg: 45.0, speed_mps: 3.0 };
    /// assert_eq!(w.arrow_spec(), "ctrx=0,ctry=0,ang=225,bwid=5,blen=20,hwid=10,hlen=10,\
    /// label=windmod,edge_color=off,vertex_color=off,fill_color=green,fill_transparency=0.2");
    /// ```
    pub fn arrow_spec(&self) -> String {
        let ang = moos_types::fmt::compact_string(crate::angle::angle360(self.dir_deg + 180.0), 1);
        format!(
            "ctrx=0,ctry=0,ang={ang},bwid=5,blen=20,hwid=10,hlen=10,label=windmod,\
             edge_color=off,vertex_color=off,fill_color=green,fill_transparency=0.2"
        )
    }
}

/// A polar plot: the percentage of the wind speed reachable at each angle off the wind,
/// given as set points `angle,pct` for angles 0..180 (mirrored for 180..360) and linearly
/// interpolated.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polar {
    points: Vec<(f64, f64)>,
}

impl Polar {
    /// Adds the set points of `hdg,val:hdg,val:...` (MOOS `addSetPoints`): each angle in
    /// [0, 180], not given before, each value >= 0; all or nothing.
    ///
    /// ```
    /// use vehicle::polar::Polar;
    /// let mut p = Polar::default();
    /// assert!(p.add_points("0,0:90,100:180,50"));
    /// assert!(!p.add_points("90,20"), "90 is already set");
    /// ```
    pub fn add_points(&mut self, spec: &str) -> bool {
        let mut new = Vec::new();
        for part in spec.split(':') {
            let Some((h, v)) = part.split_once(',') else {
                return false;
            };
            let (Some(h), Some(v)) = (
                crate::config::parse_number(h),
                crate::config::parse_number(v),
            ) else {
                return false;
            };
            let taken = |x: f64| {
                self.points.iter().any(|p| p.0 == x) || new.iter().any(|p: &(f64, f64)| p.0 == x)
            };
            if !(0.0..=180.0).contains(&h) || v < 0.0 || taken(h) {
                return false;
            }
            new.push((h, v));
        }
        self.points.extend(new);
        self.points.sort_by(|a, b| a.0.total_cmp(&b.0));
        true
    }

    /// The set points as the appcast shows them (MOOS `PolarPlot::getSpec`):
    /// `angle,value` (at most 1 and 2 decimals) joined by `:`, by angle; empty when none.
    pub fn spec(&self) -> String {
        self.points
            .iter()
            .map(|(h, v)| {
                format!(
                    "{},{}",
                    moos_types::fmt::compact_string(*h, 1),
                    moos_types::fmt::compact_string(*v, 2)
                )
            })
            .collect::<Vec<_>>()
            .join(":")
    }

    /// Whether any set point is given.
    pub fn is_set(&self) -> bool {
        !self.points.is_empty()
    }

    /// The interpolated value at an angle off the wind in [0, 180] (0 outside the set points'
    /// neighbourhood rules of `PolarPlot::interpLinear`).
    fn value_at(&self, q: f64) -> f64 {
        if !(0.0..=180.0).contains(&q) || self.points.is_empty() {
            return 0.0;
        }
        let (mut hmin, mut vmin, mut hmax, mut vmax) = (0.0, 0.0, 180.0, 0.0);
        for &(h, v) in &self.points {
            if h == q {
                return v;
            }
            if h < q {
                (hmin, vmin) = (h, v);
            }
            if h > q {
                (hmax, vmax) = (h, v);
                break;
            }
        }
        if hmin > hmax || q < hmin || q > hmax {
            return 0.0;
        }
        if hmin == hmax {
            return vmin;
        }
        vmin + (q - hmin) / (hmax - hmin) * (vmax - vmin)
    }

    /// The fraction (0..1) of the wind speed reachable on `heading_deg` with the wind from
    /// `wind_dir_deg` (MOOS `getPolarPct`: a table over whole degrees, rotated by the wind
    /// direction and rounded, values over 100 capped at 1).
    ///
    /// ```
    /// use vehicle::polar::Polar;
    /// let mut p = Polar::default();
    /// p.add_points("0,0:90,100:180,50");
    /// assert_eq!(p.fraction(90.0, 0.0), 1.0);   // beam reach
    /// assert_eq!(p.fraction(135.0, 90.0), 0.5); // 45 degrees off a wind from the east
    /// ```
    pub fn fraction(&self, heading_deg: f64, wind_dir_deg: f64) -> f64 {
        let target = (crate::angle::angle360(heading_deg) + 0.5).floor() as i64;
        // The table entry for `target`: the last whole degree h whose rotated heading rounds
        // to it (later entries overwrite earlier ones, as the C++ map does).
        let mut val = 0.0;
        for h in 0..360 {
            let rotated =
                (crate::angle::angle360(f64::from(h) + wind_dir_deg + 0.5)).floor() as i64;
            if rotated == target {
                let off = if h <= 180 { h } else { 360 - h };
                val = self.value_at(f64::from(off));
            }
        }
        (val / 100.0).min(1.0)
    }
}
