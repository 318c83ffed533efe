//! A test rig for helms built from `.bhv` text: what the helm's own tests and a user's
//! behaviour tests need to drive a [`Helm`] without a MOOSDB (the helm on its own, its
//! iterations on the caller's virtual time).
//!
//! ```
//! use helm::testing;
//! let bhv = "Behavior = BHV_ConstantHeading\n{\n name = ch\n heading = 90\n duration = no-time-limit\n}\n\
//!            Behavior = BHV_ConstantSpeed\n{\n name = cs\n speed = 1.5\n duration = no-time-limit\n}\n";
//! let mut h = testing::engaged(bhv, &[]);
//! testing::step::<&str>(&mut h, 0.0, (0.0, 0.0, 0.0, 1.0), &[]);
//! let posts = testing::step(&mut h, 1.0, (0.0, 0.0, 0.0, 1.0), &[("DEPLOY", "true")]);
//! assert_eq!(testing::texts(&posts, "DESIRED_HEADING"), ["90"]);
//! assert_eq!(testing::texts(&posts, "DESIRED_SPEED"), ["1.5"]);
//! ```

use mission::source::SourceMap;

use crate::config::Globals;
use crate::{Helm, Mail, Posting, Value};

/// The decision domain of the rig's helms: course in whole degrees, speed 0 to 4 m/s in
/// steps of 0.1.
pub const COURSE_SPEED: [(&str, &str); 2] =
    [("domain", "course:0:359:360"), ("domain", "speed:0:4:41")];

/// The mission globals of the rig's helms: the lat/long origin at 0, 0 and community `abe`.
pub fn globals() -> Globals {
    Globals {
        lat_origin: Some("0".into()),
        long_origin: Some("0".into()),
        community: Some("abe".into()),
    }
}

/// A helm of the `.bhv` text `bhv` (named `file` in its messages) with the pHelmIvP block
/// parameters `params` as given and [`globals`]; configuration errors are left for the
/// caller to read.
pub fn from_text(file: &str, bhv: &str, params: &[(&str, &str)]) -> Helm {
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text(file, bhv));
    Helm::from_parsed(params, &globals(), &parsed)
}

/// A helm that drives at once: [`COURSE_SPEED`], `start_engaged = true`, then `extra`
/// (another domain, `goals_mandatory`, ...). Panics on any configuration error.
pub fn engaged(bhv: &str, extra: &[(&str, &str)]) -> Helm {
    let mut params = COURSE_SPEED.to_vec();
    params.push(("start_engaged", "true"));
    params.extend_from_slice(extra);
    let h = from_text("test.bhv", bhv, &params);
    assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
    h
}

/// Hands the helm ownship's navigation `(x, y, heading, speed)` at `t` (`NAV_X`, `NAV_Y`,
/// `NAV_HEADING`, `NAV_SPEED`).
pub fn nav(h: &mut Helm, t: f64, (x, y, heading, speed): (f64, f64, f64, f64)) {
    h.on_mail(&[
        Mail::new("NAV_X", x, t),
        Mail::new("NAV_Y", y, t),
        Mail::new("NAV_HEADING", heading, t),
        Mail::new("NAV_SPEED", speed, t),
    ]);
}

/// One iteration at `t`: the navigation `pose` (see [`nav`]), then `mail` (string values),
/// then the helm's postings.
pub fn step<S: AsRef<str>>(
    h: &mut Helm,
    t: f64,
    pose: (f64, f64, f64, f64),
    mail: &[(&str, S)],
) -> Vec<Posting> {
    nav(h, t, pose);
    for (var, v) in mail {
        h.on_mail(&[Mail::new(var, v.as_ref(), t)]);
    }
    h.iterate(t).to_vec()
}

/// Every value posted to `var`, in order, as text (strings as they are, numbers as the
/// helm formats them).
pub fn texts(posts: &[Posting], var: &str) -> Vec<String> {
    posts
        .iter()
        .filter(|p| p.key == var)
        .map(|p| match &p.value {
            Value::String(s) => s.to_string(),
            v => v.to_string(),
        })
        .collect()
}
