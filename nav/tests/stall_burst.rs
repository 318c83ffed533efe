//! The navigator after a stalled real-time run (issue #16's robustness finding): the drivers'
//! lines held up for seconds while pNavGraph keeps iterating, then delivered in a burst
//! microseconds apart.
//!
//! In a real-time run every driver posts a line's variables when it reads the line, and the
//! MOOS client stamps each posting with its sending time (`runtime::remote`): after a stall the
//! lines of the seconds lost arrive one after another, each variable a few microseconds after
//! the last, all later than the pNavGraph iterations that ran meanwhile. Those iterations made
//! dead-reckoning keyframes (the DVL silent for `dvl_timeout_s`) with no gyro sample and no
//! AHRS yaw in their intervals: their headings were free, the window singular, and NAV_POS_STD
//! jumped to 1e5-1e7 m. The stream here is the lawnmower scenario of the other tests turned
//! into the sensor variables, fed to [`Feed`] as pNavGraph feeds it, with the burst stamped as
//! the drivers stamp it. No clock is read.

mod common;

use common::truth::{Event, Scenario, Sim};
use nav::Status;
use nav::feed::{Feed, FeedConfig};

/// The scenario's speed through the water, m/s.
const SPEED: f64 = 1.5;
/// pNavGraph's AppTick period, s.
const TICK: f64 = 0.1;
/// The time between two postings of a burst, s (a MOOS client's notify, warped).
const POST_GAP: f64 = 2e-6;

/// The variables a driver posts for one sensor event (the AHRS's rates from the last gyro
/// sample: the X150's STATUS carries both).
fn variables(e: &Event, rates: &mut [f64; 3]) -> Vec<(&'static str, f64)> {
    match e {
        Event::Dvl(m) => {
            let v = m.vel_body_mps;
            vec![
                ("DVL_VEL_X", v[0]),
                ("DVL_VEL_Y", v[1]),
                ("DVL_VEL_Z", v[2]),
                ("DVL_ALTITUDE", 20.0),
                ("DVL_FOM", m.fom_mps),
                ("DVL_WATER_TRACK", 1.0),
                ("DVL_VALID", 1.0),
            ]
        }
        Event::Gyro(m) => {
            *rates = m.rates_body_radps.map(f64::to_degrees);
            Vec::new()
        }
        Event::Att(m) => vec![
            ("AHRS_PITCH", m.pitch_rad.to_degrees()),
            ("AHRS_ROLL", m.roll_rad.to_degrees()),
            ("AHRS_ROLL_RATE", rates[0]),
            ("AHRS_PITCH_RATE", rates[1]),
            ("AHRS_YAW_RATE", rates[2]),
            ("AHRS_HEADING", m.yaw_rad.to_degrees()),
        ],
        Event::Depth(m) => vec![("PRESSURE", 101_325.0 + 997.0 * 9.81 * m.depth_m)],
        Event::Gps(m) => vec![
            ("GPS_X", m.x_m),
            ("GPS_Y", m.y_m),
            ("GPS_SATELLITES", f64::from(m.sats)),
            ("GPS_HDOP", m.hdop),
            ("GPS_FIX", 1.0),
        ],
    }
}

/// What pNavGraph posted: NAV_POS_STD at each keyframe (time, value) and the statuses seen.
struct Posted {
    pos_std: Vec<(f64, f64)>,
    statuses: Vec<Status>,
}

/// The scenario until `until`, with every driver held up from `stall_at` for `stall_s`
/// seconds: pNavGraph iterates on (its mail empty), then the lines of the stall arrive at its
/// end, each variable `POST_GAP` after the last, in the order the sensors made them.
fn run(stall_at: f64, stall_s: f64, until: f64) -> Posted {
    let mut sim = Sim::new(Scenario::default());
    let end = stall_at + stall_s;
    let mut rates = [0.0; 3];
    let mut mail: Vec<(f64, &'static str, f64)> = Vec::new();
    let mut burst = 0usize;
    loop {
        let e = sim.next_event();
        let t = e.t_s();
        if t > until {
            break;
        }
        for (name, v) in variables(&e, &mut rates) {
            let stamp = if t > stall_at && t <= end {
                burst += 1;
                end + burst as f64 * POST_GAP
            } else {
                t
            };
            mail.push((stamp, name, v));
        }
    }
    // A mailbox is handed over sorted by time (equal times keep their order).
    mail.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut feed = Feed::new(FeedConfig::default());
    let mut out = Posted {
        pos_std: Vec::new(),
        statuses: Vec::new(),
    };
    let mut next = 0;
    let mut k = 0u32;
    loop {
        k += 1;
        let now = f64::from(k) * TICK;
        if now > until {
            break;
        }
        while let Some(&(t, name, v)) = mail.get(next).filter(|m| m.0 <= now) {
            assert!(feed.take(name, v, t));
            next += 1;
        }
        feed.advance(now);
        if let Some(s) = feed.poll() {
            out.pos_std.push((now, s.estimate.pos_sigma_m));
        }
        let status = feed.status();
        if out.statuses.last() != Some(&status) {
            out.statuses.push(status);
        }
    }
    out
}

fn largest(p: &Posted, from: f64, to: f64) -> f64 {
    p.pos_std
        .iter()
        .filter(|(t, _)| (from..=to).contains(t))
        .map(|(_, v)| *v)
        .fold(0.0, f64::max)
}

/// NAV_POS_STD after a stall stays what dead reckoning over the gap allows: no more than the
/// undisturbed run's over the same time plus the distance the vehicle could travel in the
/// gap, and finite; the solver never fails; at the next surface stay the fixes bring it back
/// under 2 m.
#[test]
fn nav_pos_std_stays_physical_after_a_burst_of_held_up_lines() {
    let until = 800.0;
    let undisturbed = run(0.0, 0.0, until);
    // Mid-dive, at the surface (GPS lines in the burst), at the end of a dive: 5 to 40 s.
    for (stall_at, stall_s) in [
        (200.0, 5.0),
        (200.0, 40.0),
        (380.0, 5.0),
        (380.0, 20.0),
        (330.0, 40.0),
    ] {
        let p = run(stall_at, stall_s, until);
        let after = largest(&p, stall_at, until);
        let bound = largest(&undisturbed, stall_at, until) + SPEED * (stall_s + 1.0);
        assert!(
            after.is_finite() && after <= bound,
            "stall {stall_s} s at {stall_at} s: NAV_POS_STD up to {after:.4e} m (bound \
             {bound:.1} m)"
        );
        assert!(
            !p.statuses.contains(&Status::Degraded("solver failure")),
            "stall {stall_s} s at {stall_at} s: {:?}",
            p.statuses
        );
        // The second surface stay (720-780 s) brings the fixes back.
        let resurfaced = largest(&p, 750.0, 780.0);
        assert!(
            resurfaced < 2.0,
            "stall {stall_s} s at {stall_at} s: {resurfaced} m at the surface"
        );
        println!(
            "stall {stall_s} s at {stall_at} s: NAV_POS_STD up to {after:.2} m after it \
             (bound {bound:.1} m), {resurfaced:.2} m at the next surface stay"
        );
    }
}
