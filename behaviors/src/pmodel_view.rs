//! BHV_PModelView: draws the turn the platform model predicts towards the desired heading.
//!
//! # Conformance with BHV_PModelView (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | edge_color | | colour | white | a MOOS colour (`setColorOnString`); kept, not drawn (as the C++) | yes | done |
//! | vertex_color | | colour | white | a MOOS colour; kept, not drawn (as the C++) | yes | done |
//! | vertex_size | | number | 3 | number ≥ 0; kept, not drawn (as the C++) | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | VIEW_SEGLR | each running iteration with `DESIRED_SPEED` ≠ 0 | `pts={x,y},ray=<DESIRED_HEADING>,label=<ownship>_seglr,vertex_color=lime_green,vertex_size=2,ray_len=20,head_size=1` (one decimal in `pts` and `ray`) | done |
//! | VIEW_SEGLR | running → idle | the same seglr inactive: `...,active=false,label=<ownship>_seglr,ray_len=5,head_size=3` | done |
//! | BHV_ERROR | running without NAV_X/NAV_Y or NAV_HEADING | `No ownship X/Y info in info_buffer.`, `No ownship heading info in info_buffer.` | done |
//!
//! The behaviour never builds an objective function and posts no BHV_SETTINGS (its
//! `onSetParamComplete` is empty). The turn is pHelmIvP's platform model's
//! (`PlatModel::getTurnSeglr`): with the default holonomic model a single vertex at ownship's
//! position with a ray along the desired heading; with `pmgen = alg=dubins` the model's turn
//! spokes follow it (`pts={x,y:x1,y1:...}`, [`crate::plat_model`]). The position is the
//! model's pose, which the helm takes from NAV_X/NAV_Y each iteration all four NAV variables
//! are known.

use geometry::Attributes;
use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::param::{is_number, number};

/// Shows the platform model's turn towards the desired heading (see the module docs).
#[derive(Debug, Clone)]
pub struct PModelView {
    /// `edge_color` (kept, not drawn).
    pub edge_color: String,
    /// `vertex_color` (kept, not drawn).
    pub vertex_color: String,
    /// `vertex_size` (kept, not drawn).
    pub vertex_size: f64,
    des_hdg: f64,
    des_spd: f64,
    pose: (f64, f64),
    /// The Dubins model's spokes on the turn to the desired heading (none: holonomic).
    turn: Vec<(f64, f64)>,
}

impl Default for PModelView {
    fn default() -> Self {
        Self::new()
    }
}

impl PModelView {
    /// The MOOS defaults.
    pub fn new() -> Self {
        PModelView {
            edge_color: "white".into(),
            vertex_color: "white".into(),
            vertex_size: 3.0,
            des_hdg: 0.0,
            des_spd: 0.0,
            pose: (0.0, 0.0),
            turn: Vec::new(),
        }
    }

    /// The turn's spec (MOOS `XYSeglr::get_spec`): `pts` and `ray` with one decimal, then the
    /// drawing attributes, `ray_len` and `head_size`.
    fn seglr_spec(&self, attrs: &Attributes, ray_len: f64, head: f64) -> String {
        let mut s = format!("pts={{{:.1},{:.1}", self.pose.0, self.pose.1);
        for (x, y) in &self.turn {
            s.push_str(&format!(":{x:.1},{y:.1}"));
        }
        s.push_str(&format!("}},ray={:.1}", self.des_hdg));
        let base = s.len();
        s.push(',');
        let before = s.len();
        attrs.write_spec(&mut s, before);
        if s.len() == before {
            s.truncate(base);
        }
        s.push_str(",ray_len=");
        moos_types::fmt::compact(&mut s, ray_len, 2);
        s.push_str(",head_size=");
        moos_types::fmt::compact(&mut s, head, 1);
        s
    }

    fn update_info(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let info = ctx.info;
        let (Some(x), Some(y)) = (info.num("NAV_X"), info.num("NAV_Y")) else {
            out.error("No ownship X/Y info in info_buffer.");
            return false;
        };
        if info.num("NAV_HEADING").is_none() {
            out.error("No ownship heading info in info_buffer.");
            return false;
        }
        // The helm's platform model needs all four navigation variables.
        if info.num("NAV_SPEED").is_some() {
            self.pose = (x, y);
        }
        self.des_hdg = info.num("DESIRED_HEADING").unwrap_or(0.0);
        self.des_spd = info.num("DESIRED_SPEED").unwrap_or(0.0);
        self.turn.clear();
        if let Some(m) = info.plat_model().filter(|m| !m.is_holonomic()) {
            let path = m.turn(self.des_hdg);
            self.turn.extend(path.arc.iter().map(|p| (p.x, p.y)));
        }
        true
    }
}

impl Behavior for PModelView {
    fn kind(&self) -> &'static str {
        "BHV_PModelView"
    }

    fn default_name(&self) -> &'static str {
        "pview"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            [
                "NAV_X",
                "NAV_Y",
                "NAV_HEADING",
                "NAV_SPEED",
                "DESIRED_HEADING",
                "DESIRED_SPEED",
            ],
        );
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        match param {
            "edge_color" | "vertex_color" => {
                if !crate::color::is_color(v) {
                    return Err(ParamError::bad(param, value, "a colour"));
                }
                if param == "edge_color" {
                    self.edge_color = v.into();
                } else {
                    self.vertex_color = v.into();
                }
            }
            "vertex_size" => {
                let s = number(param, v)?;
                if !is_number(v) || s < 0.0 {
                    return Err(ParamError::bad(param, value, "a number >= 0"));
                }
                self.vertex_size = s;
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    /// The C++ `onSetParamComplete` is empty: no BHV_SETTINGS.
    fn on_set_param_complete(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        // The C++ draws whether or not the update succeeded.
        self.update_info(ctx, out);
        if self.des_spd == 0.0 {
            return None;
        }
        let attrs = Attributes {
            label: format!("{}_seglr", ctx.ownship),
            vertex_color: Some("lime_green".into()),
            vertex_size: Some(2.0),
            ..Attributes::default()
        };
        out.post("VIEW_SEGLR", self.seglr_spec(&attrs, 20.0, 1.0));
        None
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let attrs = Attributes {
            active: false,
            label: format!("{}_seglr", ctx.ownship),
            ..Attributes::default()
        };
        out.post("VIEW_SEGLR", self.seglr_spec(&attrs, 5.0, 3.0));
    }
}
