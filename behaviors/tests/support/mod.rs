//! Test support for the depth, surface, station-keep and op-region behaviours: one behaviour
//! with its common parameters, a variable map and the helm's decision domain.
#![allow(dead_code)]

use behaviors::{Behavior, Common, Ctx, Emit, MapInfo, Out, ParamError, Value, create};
use ivp::{Domain, IvpFunction, Problem};

/// The delta mission's domain (`delta.moos`): course, speed and 200 one-metre depths.
pub fn uuv_domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41", "depth:0:199:200"]).unwrap()
}

/// One behaviour under test.
pub struct Bhv {
    pub bhv: Box<dyn Behavior>,
    pub common: Common,
    pub domain: Domain,
    pub info: MapInfo,
    pub name: String,
    /// What the behaviour posted in `on_set_param_complete` at configuration.
    pub configured: Out,
}

impl Bhv {
    /// A behaviour of `kind` over `domain`, named `name`.
    pub fn new(kind: &str, name: &str, domain: Domain) -> Self {
        Bhv {
            bhv: create(kind).unwrap_or_else(|| panic!("{kind} not known to create()")),
            common: Common::new(kind),
            domain,
            info: MapInfo::new(0.0),
            name: name.to_string(),
            configured: Out::default(),
        }
    }

    /// Sets a parameter as the helm does: common ones first, then the behaviour's.
    pub fn set(&mut self, param: &str, value: &str) -> Result<(), ParamError> {
        if self.common.set_param(param, value)? {
            return Ok(());
        }
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        self.bhv.set_param(param, value, &mut self.common, &ctx)
    }

    /// Sets parameters that must be accepted.
    pub fn config(mut self, params: &[(&str, &str)]) -> Self {
        for (p, v) in params {
            self.set(p, v)
                .unwrap_or_else(|e| panic!("{p} = {v} rejected: {e}"));
        }
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        self.bhv.on_set_param_complete(&ctx, &mut self.configured);
        self
    }

    /// Sets a number in the info buffer.
    pub fn num(&mut self, var: &str, v: f64) -> &mut Self {
        self.info.set(var, Value::Double(v));
        self
    }

    /// Sets a string in the info buffer.
    pub fn text(&mut self, var: &str, v: &str) -> &mut Self {
        self.info.set(var, Value::text(v));
        self
    }

    /// Posts a string at time `t` (fresh: age 0 in an iteration at `t`).
    pub fn post(&mut self, t: f64, var: &str, v: &str) -> &mut Self {
        self.info.set_now(t);
        self.text(var, v)
    }

    /// Ownship navigation.
    pub fn nav(&mut self, x: f64, y: f64, heading: f64, speed: f64, depth: f64) -> &mut Self {
        self.num("NAV_X", x)
            .num("NAV_Y", y)
            .num("NAV_HEADING", heading)
            .num("NAV_SPEED", speed)
            .num("NAV_DEPTH", depth)
    }

    /// A running iteration at time `t`.
    pub fn run(&mut self, t: f64) -> (Option<IvpFunction>, Out) {
        self.info.set_now(t);
        let mut out = Out::default();
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        let f = self.bhv.on_run(&ctx, &mut out);
        (f, out)
    }

    /// The idle→running transition then a running iteration at time `t`.
    pub fn start(&mut self, t: f64) -> (Option<IvpFunction>, Out) {
        self.info.set_now(t);
        let mut out = Out::default();
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        self.bhv.on_idle_to_run(&ctx, &mut out);
        let f = self.bhv.on_run(&ctx, &mut out);
        (f, out)
    }

    /// An idle iteration at time `t`.
    pub fn idle(&mut self, t: f64) -> Out {
        self.info.set_now(t);
        let mut out = Out::default();
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        self.bhv.on_idle(&ctx, &mut out);
        out
    }

    /// The running→idle transition at time `t`.
    pub fn stop(&mut self, t: f64) -> Out {
        self.info.set_now(t);
        let mut out = Out::default();
        let ctx = Ctx {
            info: &self.info,
            domain: &self.domain,
            ownship: "abe",
            name: &self.name,
            perpetual: self.common.perpetual,
        };
        self.bhv.on_run_to_idle(&ctx, &mut out);
        out
    }
}

/// The value of the last posting to `var` in `out`.
pub fn posted<'a>(out: &'a Out, var: &str) -> Option<&'a Value> {
    out.emits.iter().rev().find_map(|e| match e {
        Emit::Post { var: v, value, .. } if v == var => Some(value),
        _ => None,
    })
}

/// Every posting to `var` in `out`, in order.
pub fn posted_all<'a>(out: &'a Out, var: &str) -> Vec<&'a Value> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var: v, value, .. } if v == var => Some(value),
            _ => None,
        })
        .collect()
}

/// The variables of the flags emitted in `out`.
pub fn flags(out: &Out) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } => Some(flag.var.clone()),
            _ => None,
        })
        .collect()
}

/// The decision of the given weighted functions over `domain`.
pub fn decide(domain: &Domain, fs: &[(&str, IvpFunction, f64)]) -> ivp::Decision {
    let mut p = Problem::new(domain.clone());
    for (name, f, pwt) in fs {
        p.add(name, f.clone().with_pwt(*pwt)).unwrap();
    }
    p.solve().expect("a decision")
}

/// A function's value at one `depth` (other variables of the function at index 0 unless
/// given: `speed` index for coupled speed/depth functions).
pub fn at_depth(f: &IvpFunction, depth: u32) -> f64 {
    let ix: Vec<u32> = f
        .domain()
        .vars()
        .iter()
        .map(|v| if v.name() == "depth" { depth } else { 0 })
        .collect();
    f.eval(&ix).unwrap()
}
