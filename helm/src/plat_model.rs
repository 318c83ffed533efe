//! The helm's platform-model generator (MOOS-IvP `lib_helmivp/PlatModelGenerator`, `PMGen`,
//! `PMGen_Holonomic`, `PMGen_Dubins` and pHelmIvP's `updatePlatModel` at a2a9b716; facts
//! only, coug's own code).
//!
//! `pmgen` lines configure it ([`PmGen::apply`], MOOS `setParams`): `#`-separated
//! `param=value` pieces, `alg` (holo or dubins, any case) required. A change of `alg` starts
//! a fresh generator (Dubins: radius 30, spoke_degs 10); the others go to the generator in
//! turn: the holonomic one takes anything, the Dubins one `radius`/`rad` (a number >= 0),
//! `spoke_degs`/`degs` (> 0), `mod_radius` (added, floored at 0) and `mod_spoke_degs`
//! (added, floored at 0, wrapped into `[0, 360)`). A bad piece refuses the line (a
//! configuration error): a fresh generator is dropped, while the pieces before it have
//! already changed a kept one, as in the C++.
//!
//! Each decision iteration, once `NAV_X`, `NAV_Y`, `NAV_HEADING` and `NAV_SPEED` are all
//! known, the engine makes the iteration's [`PlatModel`] ([`PmGen::generate`]), posts
//! `TURN_RATE` ([`PmGen::turn_rate`]) and the behaviours read the model through
//! `Info::plat_model`; without them the last model stays and nothing is posted.
//!
//! | pHelmIvP | coug |
//! |---|---|
//! | `pmgen` settings and their MALCONFIG rule | done |
//! | the model each decision iteration, handed to every behaviour | done |
//! | `TURN_RATE`: [`PmGen::turn_rate`] (the mean heading change between the headings of the last 5 s, degrees, negative to port; a double, on every decision iteration that made a model, whatever the `alg`, after the ledger summary (and a pending `IVPHELM_RESTARTED`), before the decision's postings, never filtered as a duplicate) | done (`helm/tests/turn_rate.rs`) |
//! | a VIEW of the model | none in pHelmIvP (BHV_PModelView draws a turn) |

use std::collections::VecDeque;

use behaviors::plat_model::{PlatModel, angle_diff, port_turn};
use moos_types::text::{is_number, parse_string, parse_string_q};

/// Which model the generator makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PmAlg {
    /// `alg=holo` (the default).
    Holonomic,
    /// `alg=dubins` with its turn radius (m) and degrees between spokes.
    Dubins {
        /// `radius` (`rad`), m.
        radius: f64,
        /// `spoke_degs` (`degs`).
        spoke_degs: f64,
    },
}

/// The platform-model generator: its settings, the heading history and the model count.
#[derive(Debug, Clone, PartialEq)]
pub struct PmGen {
    /// The algorithm and its settings.
    pub alg: PmAlg,
    count: u64,
    history: VecDeque<(f64, f64)>,
}

impl Default for PmGen {
    fn default() -> Self {
        PmGen {
            alg: PmAlg::Holonomic,
            count: 0,
            history: VecDeque::new(),
        }
    }
}

/// Seconds of heading history the turn rate averages (MOOS `m_hdg_hist_length`).
const HDG_HIST_SECS: f64 = 5.0;

/// MOOS `tokStringParse(s, key, '#', '=')`: the value of the first `key=value` piece, empty
/// when there is none or a piece before it is not one `left=right` pair.
fn tok_hash(s: &str, key: &str) -> String {
    for piece in parse_string_q(s, '#') {
        let parts = parse_string(piece, '=');
        if parts.len() != 2 {
            return String::new();
        }
        if parts[0].trim() == key {
            return parts[1].trim().to_string();
        }
    }
    String::new()
}

fn number(v: &str) -> Option<f64> {
    let t = v.trim();
    (is_number(t)).then(|| t.parse::<f64>().ok()).flatten()
}

impl PmGen {
    /// Applies one `pmgen` line (MOOS `PlatModelGenerator::setParams`, see the module docs);
    /// false when the line is refused.
    pub fn apply(&mut self, spec: &str) -> bool {
        let alg = tok_hash(spec, "alg").to_ascii_lowercase();
        let fresh = match (alg.as_str(), self.alg) {
            ("holo", PmAlg::Holonomic) | ("dubins", PmAlg::Dubins { .. }) => None,
            ("holo", _) => Some(PmAlg::Holonomic),
            ("dubins", _) => Some(PmAlg::Dubins {
                radius: 30.0,
                spoke_degs: 10.0,
            }),
            _ => return false,
        };
        let mut target = fresh.unwrap_or(self.alg);
        for piece in spec.split('#') {
            let (param, value) = piece.split_once('=').unwrap_or((piece, ""));
            let (param, value) = (param.trim(), value.trim());
            if param == "alg" {
                continue;
            }
            let ok = match &mut target {
                PmAlg::Holonomic => true,
                PmAlg::Dubins { radius, spoke_degs } => {
                    let num = number(value);
                    match param {
                        "radius" | "rad" => num.filter(|v| *v >= 0.0).map(|v| *radius = v),
                        "spoke_degs" | "degs" => num.filter(|v| *v > 0.0).map(|v| *spoke_degs = v),
                        "mod_radius" => num.map(|v| *radius = (*radius + v).max(0.0)),
                        "mod_spoke_degs" => num
                            .map(|v| *spoke_degs = geometry::angle_360((*spoke_degs + v).max(0.0))),
                        _ => None,
                    }
                    .is_some()
                }
            };
            if !ok {
                if fresh.is_none() {
                    // The kept generator keeps what the pieces before this one changed.
                    self.alg = target;
                }
                return false;
            }
        }
        self.alg = target;
        true
    }

    /// The model at ownship's pose for this iteration at helm time `now` (MOOS `generate`):
    /// the heading joins the history (not at time 0, as the C++), and the model is numbered.
    pub fn generate(&mut self, now: f64, x: f64, y: f64, h: f64, v: f64) -> PlatModel {
        if now != 0.0 {
            self.history.push_front((h, now));
            while let Some(&(_, t)) = self.history.back() {
                if now - t > HDG_HIST_SECS {
                    self.history.pop_back();
                } else {
                    break;
                }
            }
        }
        let m = match self.alg {
            PmAlg::Holonomic => PlatModel::holonomic(x, y, h, v),
            PmAlg::Dubins { radius, spoke_degs } => {
                PlatModel::dubins(x, y, h, v, radius, spoke_degs)
            }
        };
        let m = m.with_id(self.count);
        self.count += 1;
        m
    }

    /// The mean change of heading between the history's successive headings, degrees per
    /// iteration, negative to port (MOOS `getTurnRate`/`getHdgAvg`); −1 with no history.
    pub fn turn_rate(&self) -> f64 {
        let mut it = self.history.iter();
        let Some(&(mut prev, newest)) = it.next() else {
            return -1.0;
        };
        let (mut total, mut count) = (0.0, 0u32);
        for &(hdg, t) in it {
            if newest - t > HDG_HIST_SECS {
                break;
            }
            let d = angle_diff(hdg, prev);
            total += if port_turn(hdg, prev) { -d } else { d };
            prev = hdg;
            count += 1;
        }
        if count == 0 {
            0.0
        } else {
            total / f64::from(count)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pmgen_lines_follow_set_params() {
        let mut g = PmGen::default();
        assert_eq!(g.alg, PmAlg::Holonomic);
        assert!(g.apply("alg=HOLO#anything=1"));
        assert!(g.apply("alg=dubins#rad=12#degs=15"));
        assert_eq!(
            g.alg,
            PmAlg::Dubins {
                radius: 12.0,
                spoke_degs: 15.0
            }
        );
        // Same alg: the settings change in place, mod_* add.
        assert!(g.apply("alg=dubins#mod_radius=-20#mod_spoke_degs=350"));
        assert_eq!(
            g.alg,
            PmAlg::Dubins {
                radius: 0.0,
                spoke_degs: 5.0
            }
        );
        // A bad piece on the kept generator: the pieces before it stay applied.
        assert!(!g.apply("alg=dubins#radius=7#degs=0"));
        assert_eq!(
            g.alg,
            PmAlg::Dubins {
                radius: 7.0,
                spoke_degs: 5.0
            }
        );
        // A bad piece on a fresh generator: the old one stays whole.
        let mut h = PmGen::default();
        assert!(!h.apply("alg=dubins#radius=7#speed=2"));
        assert_eq!(h.alg, PmAlg::Holonomic);
        for bad in ["true", "alg=ackermann", "radius=3", "alg=dubins#rad=-1"] {
            assert!(!PmGen::default().apply(bad), "{bad}");
        }
        // A fresh Dubins generator has MOOS's defaults.
        let mut d = PmGen::default();
        assert!(d.apply("alg=dubins"));
        assert_eq!(
            d.alg,
            PmAlg::Dubins {
                radius: 30.0,
                spoke_degs: 10.0
            }
        );
    }

    #[test]
    fn generate_numbers_models_and_keeps_five_seconds_of_headings() {
        let mut g = PmGen::default();
        assert!(g.apply("alg=dubins#radius=10#degs=30"));
        let m = g.generate(10.0, 1.0, 2.0, 90.0, 1.5);
        assert_eq!((m.id(), m.radius(), m.star_spokes().len()), (0, 10.0, 6));
        assert_eq!(g.turn_rate(), 0.0, "one heading: no change yet");
        let _ = g.generate(11.0, 1.0, 2.0, 100.0, 1.5);
        let m = g.generate(12.0, 1.0, 2.0, 95.0, 1.5);
        assert_eq!(m.id(), 2);
        // Each heading against the next newer one, a turn to port negative: 100 then 95 is
        // -5, 90 then 100 is +10; the mean is 2.5.
        assert_eq!(g.turn_rate(), 2.5);
        // Headings older than 5 s leave the history.
        let _ = g.generate(17.5, 1.0, 2.0, 95.0, 1.5);
        assert_eq!(g.history.len(), 1);
    }
}
