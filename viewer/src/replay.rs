//! `coug view LOG.alog`: a finished mission replayed on the same page, like alogview. The
//! log's viewed records (NODE_REPORT*, VIEW_*, APPCAST) are kept in time order
//! ([`Replay`], pure); the scene at a time is the scene those records up to it build, so a
//! seek rebuilds it from the start and playing applies the records as the playhead passes
//! them. [`drive`] moves the playhead at the chosen speed and takes the page's controls
//! (play, pause, seek, speed).

use std::sync::Arc;
use std::time::Duration;

use serde_json::json;

use crate::scene::{Scene, viewed_variables};
use crate::server::{ReplayControl, Viewer};

/// A log's viewed records, in time order, with the times as MOOS times.
#[derive(Debug, Clone, Default)]
pub struct Replay {
    /// `(MOOS time, variable, string value)`.
    records: Vec<(f64, String, String)>,
    /// LOGSTART (MOOS time of the log's time 0).
    start: f64,
    /// Seconds from the start to the last record.
    duration: f64,
}

impl Replay {
    /// Keeps the viewed string records of `log`.
    pub fn from_alog(log: &alog::Alog) -> Replay {
        let viewed = viewed_variables();
        let start = log.log_start.unwrap_or(0.0);
        let mut records: Vec<(f64, String, String)> = log
            .entries
            .iter()
            .filter(|e| viewed.contains(&e.var.as_str()))
            .filter_map(|e| {
                e.value
                    .as_str()
                    .map(|s| (start + e.time, e.var.clone(), s.to_string()))
            })
            .collect();
        records.sort_by(|a, b| a.0.total_cmp(&b.0));
        let duration = log.entries.iter().map(|e| e.time).fold(0.0f64, f64::max);
        Replay {
            records,
            start,
            duration,
        }
    }

    /// Seconds the log spans.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The number of viewed records.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// True without any viewed record.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// The index of the first record after `t` seconds from the start.
    pub fn index_after(&self, t: f64) -> usize {
        let at = self.start + t;
        self.records.partition_point(|r| r.0 <= at)
    }

    /// Applies records `from..to` to `scene`, then ticks it to the time `t` (seconds from
    /// the start). Rejected records are skipped.
    pub fn apply(&self, scene: &mut Scene, from: usize, to: usize, t: f64) {
        for (time, var, value) in &self.records[from.min(to)..to.min(self.records.len())] {
            let _ = scene.apply(var, value, *time);
        }
        scene.tick(self.start + t);
    }

    /// The scene at `t` seconds from the start, built from nothing.
    pub fn scene_at(&self, scene: &mut Scene, t: f64) {
        let to = self.index_after(t);
        self.apply(scene, 0, to, t);
    }
}

/// The playhead.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Head {
    t: f64,
    playing: bool,
    speed: f64,
    next: usize,
}

fn publish(viewer: &Viewer, replay: &Replay, h: &Head) {
    viewer.set_status(json!({
        "t": h.t,
        "start": replay.start,
        "end": replay.duration,
        "playing": h.playing,
        "speed": h.speed,
    }));
}

/// Replays `replay` into `viewer` until the task is dropped: starts paused at 0 (`playing`:
/// playing at `speed`), then follows the page's controls. The playhead moves every `step`
/// of wall time.
pub async fn drive(
    viewer: Arc<Viewer>,
    replay: Arc<Replay>,
    playing: bool,
    speed: f64,
    step: Duration,
) {
    let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel();
    viewer.set_replay_control(tx);
    let mut h = Head {
        t: 0.0,
        playing,
        speed: if speed > 0.0 { speed } else { 1.0 },
        next: 0,
    };
    viewer.rebuild(|s| replay.scene_at(s, 0.0));
    h.next = replay.index_after(0.0);
    publish(&viewer, &replay, &h);
    let mut tick = tokio::time::interval(step);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut last = tokio::time::Instant::now();
    loop {
        tokio::select! {
            c = rx.recv() => {
                let Some(c) = c else { break };
                match c {
                    ReplayControl::Play => {
                        if h.t >= replay.duration {
                            h.t = 0.0;
                            viewer.rebuild(|s| replay.scene_at(s, 0.0));
                            h.next = replay.index_after(0.0);
                        }
                        h.playing = true;
                    }
                    ReplayControl::Pause => h.playing = false,
                    ReplayControl::Speed(x) => h.speed = x,
                    ReplayControl::Seek(t) => {
                        h.t = t.clamp(0.0, replay.duration);
                        viewer.rebuild(|s| replay.scene_at(s, h.t));
                        h.next = replay.index_after(h.t);
                    }
                }
                last = tokio::time::Instant::now();
                publish(&viewer, &replay, &h);
            }
            _ = tick.tick() => {
                let now = tokio::time::Instant::now();
                let dt = now.duration_since(last).as_secs_f64();
                last = now;
                if !h.playing {
                    continue;
                }
                h.t = (h.t + dt * h.speed).min(replay.duration);
                let to = replay.index_after(h.t);
                let (from, t) = (h.next, h.t);
                viewer.update(|s| replay.apply(s, from, to, t));
                h.next = to;
                if h.t >= replay.duration {
                    h.playing = false;
                }
                publish(&viewer, &replay, &h);
            }
        }
    }
}
