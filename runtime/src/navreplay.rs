//! Navigation from a log: the sensor variables of an alog replayed through [`nav::feed::Feed`]
//! (the adapter `pNavGraph` runs live, so the replay navigates as the vehicle did), and the
//! figures of a navigation against the simulator's truth (`SIM_X`, `SIM_Y`): RMSE, maximum
//! error, the error at each resurfacing, for the estimate and for dead reckoning.
//!
//! `coug nav LOG.alog [-o OUT.csv]` is [`replay`], [`write_csv`] and [`Figures::report`]; the
//! closed-loop tests use [`live`] (the `NAV_*`/`DR_*` the app posted) with the same figures.

use std::fmt::Write as _;

use nav::feed::{Feed, FeedConfig, INPUTS, Snapshot};
use nav::{DiveReport, Status};

/// One point of a horizontal track: time (s, the log's), east, north (m).
pub type Point = (f64, f64, f64);

/// One row of a replayed trajectory (a keyframe).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Log time, s.
    pub t_s: f64,
    /// The estimate and its status.
    pub snapshot: Snapshot,
}

/// A navigation: the estimated and dead-reckoned tracks and the dive reports.
#[derive(Debug, Clone, Default)]
pub struct Navigation {
    /// Replayed keyframes (empty for [`live`]).
    pub rows: Vec<Row>,
    /// The estimate's track.
    pub estimate: Vec<Point>,
    /// The dead-reckoning track.
    pub dead_reckoning: Vec<Point>,
    /// The dive reports, with the log time of their fix.
    pub dives: Vec<(f64, DiveReport)>,
}

/// Replays the sensor variables of `log` through a [`Feed`] with `cfg`: each record is taken
/// at its log time, and the navigator's time advances before the first record of each new
/// time (as the app's iterations do).
pub fn replay(log: &alog::Alog, cfg: FeedConfig) -> Navigation {
    let mut feed = Feed::new(cfg);
    let mut out = Navigation::default();
    let mut last_t = f64::NEG_INFINITY;
    for e in &log.entries {
        if !INPUTS.contains(&e.var.as_str()) {
            continue;
        }
        let Some(v) = e.value.as_f64() else { continue };
        if e.time != last_t {
            feed.advance(e.time);
            collect(&mut feed, &mut out, last_t);
            last_t = e.time;
        }
        feed.take(&e.var, v, e.time);
        collect(&mut feed, &mut out, e.time);
    }
    out
}

fn collect(feed: &mut Feed, out: &mut Navigation, t_s: f64) {
    let Some(s) = feed.poll() else { return };
    let e = &s.estimate;
    out.estimate.push((t_s, e.x_m, e.y_m));
    if let Some([x, y, _]) = s.dead_reckoning {
        out.dead_reckoning.push((t_s, x, y));
    }
    if let Some(d) = s.dive {
        out.dives.push((t_s, d));
    }
    out.rows.push(Row { t_s, snapshot: s });
}

/// The `(time, x, y)` track of two variables (a point each time the second one arrives with
/// the first known).
pub fn track(log: &alog::Alog, xvar: &str, yvar: &str) -> Vec<Point> {
    let mut x = None;
    let mut out = Vec::new();
    for e in &log.entries {
        if e.var == xvar {
            x = e.value.as_f64();
        } else if e.var == yvar
            && let (Some(x), Some(y)) = (x, e.value.as_f64())
        {
            out.push((e.time, x, y));
        }
    }
    out
}

/// Parses a `NAV_DIVE_REPORT` string (`dive=N,dist=D,correction=C,ratio_pct=R,...`).
pub fn parse_dive_report(s: &str) -> Option<DiveReport> {
    let get = |k: &str| {
        s.split(',')
            .filter_map(|p| p.split_once('='))
            .find(|(key, _)| key.trim() == k)
            .and_then(|(_, v)| v.trim().parse::<f64>().ok())
    };
    Some(DiveReport {
        dive: get("dive")? as u32,
        distance_m: get("dist")?,
        correction_m: get("correction")?,
        ratio_pct: get("ratio_pct")?,
        start_t_s: get("start").unwrap_or(f64::NAN),
        surface_t_s: get("surface").unwrap_or(f64::NAN),
        fix_t_s: get("fix").unwrap_or(f64::NAN),
    })
}

/// The navigation the app posted live: `NAV_X/Y`, `<dr>_X/Y` and `NAV_DIVE_REPORT` (its
/// log time is the fix's).
pub fn live(log: &alog::Alog, dr_prefix: &str) -> Navigation {
    Navigation {
        rows: Vec::new(),
        estimate: track(log, "NAV_X", "NAV_Y"),
        dead_reckoning: track(log, &format!("{dr_prefix}_X"), &format!("{dr_prefix}_Y")),
        dives: log
            .entries
            .iter()
            .filter(|e| e.var == "NAV_DIVE_REPORT")
            .filter_map(|e| Some((e.time, parse_dive_report(e.value.as_str()?)?)))
            .collect(),
    }
}

/// The truth's track (`SIM_X`, `SIM_Y`), empty when the log has none.
pub fn truth(log: &alog::Alog) -> Vec<Point> {
    track(log, "SIM_X", "SIM_Y")
}

/// The truth at time `t` (the latest record at or before it), if any.
fn truth_at(truth: &[Point], t: f64) -> Option<(f64, f64)> {
    let i = truth.partition_point(|p| p.0 <= t);
    let p = truth.get(i.checked_sub(1)?)?;
    Some((p.1, p.2))
}

/// Horizontal errors of a track against the truth.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Errors {
    /// Points compared.
    pub n: usize,
    /// Root mean square horizontal error, m.
    pub rmse_m: f64,
    /// Largest horizontal error, m.
    pub max_m: f64,
}

/// The errors of `track` against `truth`, over the points at or after `from_t`.
pub fn errors(track: &[Point], truth: &[Point], from_t: f64) -> Errors {
    let mut e = Errors::default();
    let mut sum = 0.0;
    for &(t, x, y) in track.iter().filter(|p| p.0 >= from_t) {
        let Some((tx, ty)) = truth_at(truth, t) else {
            continue;
        };
        let d = (x - tx).hypot(y - ty);
        e.n += 1;
        sum += d * d;
        e.max_m = e.max_m.max(d);
    }
    if e.n > 0 {
        e.rmse_m = (sum / e.n as f64).sqrt();
    }
    e
}

/// The error of a track at time `t`: its last point strictly before `t` (so at a dive's fix,
/// the estimate before the fix corrects it) against the truth at that point's time.
pub fn error_before(track: &[Point], truth: &[Point], t: f64) -> Option<f64> {
    let i = track.partition_point(|p| p.0 < t);
    let &(pt, x, y) = track.get(i.checked_sub(1)?)?;
    let (tx, ty) = truth_at(truth, pt)?;
    Some((x - tx).hypot(y - ty))
}

/// One dive's figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiveFigures {
    /// Log time of the first good fix after the dive, s.
    pub fix_t_s: f64,
    /// The navigator's report.
    pub report: DiveReport,
    /// Estimate error just before that fix, m.
    pub estimate_error_m: Option<f64>,
    /// Dead-reckoning error at the same time, m.
    pub dead_reckoning_error_m: Option<f64>,
}

/// Seconds after the first dive's fix from which [`Figures::estimate_after_first_fix`]
/// counts: the fix enters at the next keyframe, and the estimate at its own time is still the
/// dive's.
pub const SETTLE_S: f64 = 5.0;

/// The figures of a navigation against the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Figures {
    /// The estimate's errors over the whole track.
    pub estimate: Errors,
    /// The estimate's errors from [`SETTLE_S`] after the first dive's fix.
    pub estimate_after_first_fix: Errors,
    /// Dead reckoning's errors over the whole track.
    pub dead_reckoning: Errors,
    /// Per dive.
    pub dives: Vec<DiveFigures>,
}

impl Figures {
    /// The figures of `nav` against `truth`.
    pub fn of(nav: &Navigation, truth: &[Point]) -> Figures {
        let first_fix = nav.dives.first().map_or(f64::INFINITY, |d| d.0 + SETTLE_S);
        Figures {
            estimate: errors(&nav.estimate, truth, f64::NEG_INFINITY),
            estimate_after_first_fix: errors(&nav.estimate, truth, first_fix),
            dead_reckoning: errors(&nav.dead_reckoning, truth, f64::NEG_INFINITY),
            dives: nav
                .dives
                .iter()
                .map(|&(t, report)| DiveFigures {
                    fix_t_s: t,
                    report,
                    estimate_error_m: error_before(&nav.estimate, truth, t),
                    dead_reckoning_error_m: error_before(&nav.dead_reckoning, truth, t),
                })
                .collect(),
        }
    }

    /// The figures as text, one line each.
    pub fn report(&self) -> String {
        let mut s = String::new();
        let line = |s: &mut String, what: &str, e: &Errors| {
            let _ = writeln!(
                s,
                "{what:<28} RMSE {:>7.2} m   max {:>7.2} m   ({} points)",
                e.rmse_m, e.max_m, e.n
            );
        };
        line(&mut s, "estimate:", &self.estimate);
        line(
            &mut s,
            "estimate after first fix:",
            &self.estimate_after_first_fix,
        );
        line(&mut s, "dead reckoning:", &self.dead_reckoning);
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
        for d in &self.dives {
            let _ = writeln!(
                s,
                "dive {:>2} (fix at {:>7.1} s): dist {:>7.1} m  correction {:>6.2} m ({:.2} %)  \
                 error at resurfacing: estimate {} m, dead reckoning {} m",
                d.report.dive,
                d.fix_t_s,
                d.report.distance_m,
                d.report.correction_m,
                d.report.ratio_pct,
                opt(d.estimate_error_m),
                opt(d.dead_reckoning_error_m)
            );
        }
        s
    }
}

/// Writes the replayed trajectory as CSV: `time,x,y,depth,heading,sigma,status,
/// heading_bias,current_x,current_y,dr_x,dr_y,dr_depth` (s, m, m, m, deg, m, text, deg, m/s,
/// m/s, m, m, m; dead reckoning empty before its first fix).
pub fn write_csv(nav: &Navigation, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    writeln!(
        out,
        "time,x,y,depth,heading,sigma,status,heading_bias,current_x,current_y,dr_x,dr_y,dr_depth"
    )?;
    for r in &nav.rows {
        let e = &r.snapshot.estimate;
        let status = match r.snapshot.status {
            Status::Ok => "ok".to_string(),
            s => s.describe().replace(',', ";"),
        };
        let dr = r
            .snapshot
            .dead_reckoning
            .map_or(",,".to_string(), |[x, y, d]| {
                format!("{x:.3},{y:.3},{d:.3}")
            });
        writeln!(
            out,
            "{:.3},{:.3},{:.3},{:.3},{:.2},{:.3},{status},{:.3},{:.4},{:.4},{dr}",
            r.t_s,
            e.x_m,
            e.y_m,
            e.depth_m,
            e.heading_rad.to_degrees(),
            e.pos_sigma_m,
            e.heading_bias_rad.to_degrees(),
            e.current_east_mps,
            e.current_north_mps,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dive_reports_parse_back() {
        let r = parse_dive_report(
            "dive=2,dist=412.35,correction=2.50,ratio_pct=0.61,start=10.00,surface=300.50,fix=303.25",
        )
        .unwrap();
        assert_eq!(r.dive, 2);
        assert_eq!(
            (r.distance_m, r.correction_m, r.ratio_pct),
            (412.35, 2.5, 0.61)
        );
        assert_eq!(r.fix_t_s, 303.25);
        assert!(parse_dive_report("dive=x").is_none());
    }

    #[test]
    fn errors_against_the_latest_truth() {
        let truth = [(0.0, 0.0, 0.0), (1.0, 1.0, 0.0), (2.0, 2.0, 0.0)];
        let track = [(0.5, 0.0, 3.0), (1.5, 1.0, 4.0), (2.5, 5.0, 4.0)];
        let e = errors(&track, &truth, 0.0);
        assert_eq!(e.n, 3);
        assert_eq!(e.max_m, 5.0);
        assert!((e.rmse_m - ((9.0 + 16.0 + 25.0) / 3.0f64).sqrt()).abs() < 1e-12);
        assert_eq!(errors(&track, &truth, 1.0).n, 2);
        assert_eq!(error_before(&track, &truth, 1.5), Some(3.0));
        assert_eq!(error_before(&track, &truth, 0.5), None);
    }
}
