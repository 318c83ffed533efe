//! The velocity filter of BHV_AvdColregsV22/V26 (MOOS-IvP `VelocityFilter` at a2a9b716):
//! `velocity_filter = min_spd=0.5, max_spd=2, pct=40` shrinks the CPA utility distances when
//! both vehicles are slow.
//!
//! With `v` the faster of ownship and the contact: the factor is `(pct + (v − min) / (max −
//! min) · (100 − pct)) / 100`, clipped to `[0, 1]`, between the two speeds. At or above
//! `max_spd` the C++ returns 100 and at or below `min_spd` it returns `pct` itself (not divided
//! by 100), so the distances are then multiplied by 100 or by `pct`; coug keeps those values.

/// A velocity filter; `None` fields were not given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityFilter {
    /// `min_spd`, m/s (−1 unset).
    pub min_spd: f64,
    /// `max_spd`, m/s (−1 unset).
    pub max_spd: f64,
    /// `pct`, the factor in percent at or below `min_spd` (−1 unset).
    pub min_spd_pct: f64,
}

impl Default for VelocityFilter {
    fn default() -> Self {
        VelocityFilter {
            min_spd: -1.0,
            max_spd: -1.0,
            min_spd_pct: -1.0,
        }
    }
}

impl VelocityFilter {
    /// Reads `min_spd=..,max_spd=..,pct=..` (names any case, unknown or non-numeric parts
    /// ignored); `None` when the result is not [`VelocityFilter::valid`] (the C++ then keeps
    /// an unset filter and refuses the parameter).
    pub fn parse(s: &str) -> Option<Self> {
        let mut f = VelocityFilter::default();
        for part in s.split(',') {
            let (k, v) = part.split_once('=').unwrap_or((part, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            if !crate::param::is_number(v) {
                continue;
            }
            let d = geometry::atof(v);
            match k.as_str() {
                "min_spd" => f.min_spd = d,
                "max_spd" => f.max_spd = d,
                "pct" => f.min_spd_pct = d,
                _ => {}
            }
        }
        f.valid().then_some(f)
    }

    /// Both speeds set and ordered, `pct` at most 100 (MOOS `valid`; an unset `pct` passes,
    /// as in the C++).
    pub fn valid(&self) -> bool {
        self.min_spd >= 0.0
            && self.max_spd >= 0.0
            && self.min_spd_pct <= 100.0
            && self.min_spd <= self.max_spd
    }

    /// The factor for ownship speed `osv` and contact speed `cnv` (MOOS `getFilterPct`).
    pub fn factor(&self, osv: f64, cnv: f64) -> f64 {
        let v = osv.max(cnv);
        if v >= self.max_spd {
            return 100.0;
        }
        if v <= self.min_spd {
            return self.min_spd_pct;
        }
        let spd_range = self.max_spd - self.min_spd;
        if spd_range <= 0.0 {
            return 100.0;
        }
        let pct = (self.min_spd_pct + (v - self.min_spd) / spd_range * (100.0 - self.min_spd_pct))
            / 100.0;
        pct.clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_and_its_cpp_ends() {
        let f = VelocityFilter::parse("min_spd=1, MAX_SPD=3, pct=40").unwrap();
        // Between: (40 + (2 - 1) / 2 · 60) / 100 = 0.7, the faster vehicle counting.
        assert!((f.factor(0.5, 2.0) - 0.7).abs() < 1e-12);
        assert_eq!(f.factor(3.0, 0.0), 100.0);
        assert_eq!(f.factor(0.5, 0.5), 40.0);
        assert!(VelocityFilter::parse("min_spd=3,max_spd=1").is_none());
        assert!(VelocityFilter::parse("min_spd=1,max_spd=3,pct=101").is_none());
        assert!(VelocityFilter::parse("max_spd=3").is_none());
        assert!(VelocityFilter::parse("min_spd=1,max_spd=3").is_some());
    }
}
