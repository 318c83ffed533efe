//! A deterministic acoustic channel simulator (issue #16, point 3): pure, time as an
//! argument, random draws from one seed.
//!
//! Nodes have positions ([`Channel::add_node`], [`Channel::set_position`]); a node
//! [`transmit`](Channel::transmit)s a payload at a time; [`step`](Channel::step) returns the
//! receptions complete by then. The model:
//!
//! - **Delay and airtime.** A packet sent at `t` from a node at range `d` starts arriving at
//!   `t + d / c` and is received whole at `t + d / c + airtime`, with `airtime = overhead +
//!   8 * bytes / bit_rate`. The geometry is the one at `t` (a vehicle at 2 m/s moves 4 m in the
//!   2 s a packet takes over 3 km).
//! - **Range.** Nodes past `max_range_m` never hear the packet (nor are they disturbed by it).
//! - **Loss.** Within range, a packet is decoded with probability
//!   [`LossCurve::success`]`(range, bytes)`, falling with range and with size.
//! - **Half-duplex.** A node cannot hear while it transmits: an arrival that overlaps any of
//!   the receiver's own transmissions is lost. A node cannot start a transmission before its
//!   previous one ends ([`TxError::Busy`]).
//! - **Collisions.** Two arrivals at one receiver whose intervals overlap are both lost. Every
//!   arrival within range occupies the receiver, even one that the loss draw would have lost
//!   (its energy is still in the water).
//! - **USBL.** Every reception carries a fix of the sender as seen from the receiver: range,
//!   azimuth and elevation with Gaussian noise ([`UsblNoise`]). A real SeaTrac measures range
//!   only on a two-way exchange; the app that reads the fix decides which parts it trusts.
//!
//! Each arrival is counted once in [`Stats`], in this order of causes: half-duplex,
//! collision, random loss, else delivered.
//!
//! Determinism: every draw (one uniform for the loss, three normals for the fix) is made at
//! transmit time, for each node in range in the order nodes were added, whatever their
//! outcome, from a SplitMix64 stream seeded by [`Config::seed`]. The same calls give the same
//! receptions, bit for bit, whatever the step size. Transmit times must not go back before
//! the last step ([`TxError::TimeWentBack`]): then an arrival complete at a step can no longer
//! meet a new one, and what a step returns is final.
//!
//! # Against LSTS DUNE's `Simulators/AcousticModem` and MOOS-IvP's uFldNodeComms
//!
//! | | DUNE | uFldNodeComms | achannel |
//! |---|---|---|---|
//! | propagation delay | `d / 1500` | none | `d / c`, `c` configurable (1500 m/s) |
//! | airtime | `bytes * 8 / bit_rate` | none | the same plus a fixed overhead |
//! | maximum range | 3000 m | comms_range 100 m | `max_range_m` (3000 m) |
//! | loss | `exp(-d^2 / (2 * 750^2)) * exp(-n^2 / (2 * 800^2))` | a drop percentage | the same Gaussian by default, or a piecewise-linear curve over range times the size factor |
//! | half-duplex | a busy receiver drops an arrival | no | arrivals overlapping the receiver's own transmissions are lost; a busy sender is refused |
//! | collisions | an arrival while receiving drops both | no | any two overlapping arrivals at a receiver are both lost, also a third or more |
//! | USBL fix | no | no | range, azimuth and elevation with Gaussian noise |
//! | seeded | yes | no | yes, draws independent of the outcomes and of the step size |
//!
//! ```
//! use achannel::{Channel, Config, LossCurve, Position};
//! // No random loss: success 1 at every range and size.
//! let lossless = LossCurve::Table { points: vec![(0.0, 1.0)], size_sigma_bytes: f64::INFINITY };
//! let mut ch = Channel::new(Config { seed: 7, loss: lossless, ..Config::default() });
//! let base = ch.add_node(Position::new(0.0, 0.0, 0.0));
//! let auv = ch.add_node(Position::new(300.0, 400.0, 0.0)); // 500 m north-east
//! ch.transmit(base, b"0123456789", 0.0).unwrap(); // 80 bits at 100 bit/s: 0.8 s
//! assert!(ch.step(1.0).is_empty()); // received whole at 0.333 + 0.8 s
//! let rx = ch.step(1.2);
//! assert_eq!((rx.len(), rx[0].to, &rx[0].payload[..]), (1, auv, &b"0123456789"[..]));
//! assert!((rx[0].arrival_s - (500.0 / 1500.0 + 0.8)).abs() < 1e-12);
//! // The base is at bearing 216.87 degrees from the vehicle, give or take the USBL noise.
//! assert!((rx[0].usbl.azimuth_deg - 216.87).abs() < 5.0);
//! ```

#![warn(missing_docs)]

use std::sync::Arc;

/// A node's index in the channel (in the order nodes were added).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub usize);

/// A position in the mission's local frame: x east and y north in metres, depth positive down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Position {
    /// East, metres.
    pub x_m: f64,
    /// North, metres.
    pub y_m: f64,
    /// Depth, metres, positive down.
    pub depth_m: f64,
}

impl Position {
    /// A position from x, y and depth.
    pub fn new(x_m: f64, y_m: f64, depth_m: f64) -> Self {
        Self { x_m, y_m, depth_m }
    }

    /// Straight-line distance, metres.
    pub fn distance(&self, o: &Position) -> f64 {
        let (dx, dy, dz) = (o.x_m - self.x_m, o.y_m - self.y_m, o.depth_m - self.depth_m);
        (dx * dx + dy * dy + dz * dz).sqrt()
    }
}

/// The probability that a packet within range is decoded.
#[derive(Debug, Clone, PartialEq)]
pub enum LossCurve {
    /// DUNE's model: `exp(-d^2 / (2 range_sigma^2)) * exp(-n^2 / (2 size_sigma^2))`, `d` in
    /// metres and `n` in bytes.
    Gaussian {
        /// Range scale, metres (DUNE: 750).
        range_sigma_m: f64,
        /// Size scale, bytes (DUNE: 800).
        size_sigma_bytes: f64,
    },
    /// A success probability over range, linear between the points (sorted by range; held
    /// flat before the first and after the last), times the size factor
    /// `exp(-n^2 / (2 size_sigma^2))`.
    Table {
        /// `(range_m, success probability)` points.
        points: Vec<(f64, f64)>,
        /// Size scale, bytes.
        size_sigma_bytes: f64,
    },
}

impl LossCurve {
    /// DUNE's curve (750 m, 800 bytes).
    pub fn dune() -> Self {
        LossCurve::Gaussian {
            range_sigma_m: 750.0,
            size_sigma_bytes: 800.0,
        }
    }

    /// The success probability of a packet of `bytes` bytes at `range_m` metres, in [0, 1].
    pub fn success(&self, range_m: f64, bytes: usize) -> f64 {
        let n = bytes as f64;
        let gauss = |x: f64, s: f64| {
            if s > 0.0 {
                (-x * x / (2.0 * s * s)).exp()
            } else {
                0.0
            }
        };
        let p = match self {
            LossCurve::Gaussian {
                range_sigma_m,
                size_sigma_bytes,
            } => gauss(range_m, *range_sigma_m) * gauss(n, *size_sigma_bytes),
            LossCurve::Table {
                points,
                size_sigma_bytes,
            } => interpolate(points, range_m) * gauss(n, *size_sigma_bytes),
        };
        if p.is_nan() { 0.0 } else { p.clamp(0.0, 1.0) }
    }
}

fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return 0.0;
    };
    if x <= first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    for w in points.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if x >= x0 && x <= x1 {
            return if x1 > x0 {
                y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            } else {
                y1
            };
        }
    }
    last.1
}

/// Standard deviations of the USBL fix's noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UsblNoise {
    /// Azimuth, degrees.
    pub azimuth_sigma_deg: f64,
    /// Elevation, degrees.
    pub elevation_sigma_deg: f64,
    /// Range, metres.
    pub range_sigma_m: f64,
}

impl Default for UsblNoise {
    /// The CoUGARs HoloOcean stand-in's figures: 1 degree, 0.1 m.
    fn default() -> Self {
        Self {
            azimuth_sigma_deg: 1.0,
            elevation_sigma_deg: 1.0,
            range_sigma_m: 0.1,
        }
    }
}

/// The channel's parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Speed of sound, m/s (1500).
    pub sound_speed_mps: f64,
    /// Acoustic bit rate, bits per second (100).
    pub bit_rate_bps: f64,
    /// Fixed time added to every packet's airtime (preamble, headers), seconds (0).
    pub overhead_s: f64,
    /// Nodes beyond this range never hear a packet, metres (3000, as DUNE).
    pub max_range_m: f64,
    /// Largest payload, bytes (31, a SeaTrac DAT packet).
    pub max_payload: usize,
    /// Success probability over range and size (DUNE's by default).
    pub loss: LossCurve,
    /// Noise of the USBL fix.
    pub usbl: UsblNoise,
    /// Seed of every random draw.
    pub seed: u64,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            sound_speed_mps: 1500.0,
            bit_rate_bps: 100.0,
            overhead_s: 0.0,
            max_range_m: 3000.0,
            max_payload: 31,
            loss: LossCurve::dune(),
            usbl: UsblNoise::default(),
            seed: 0,
        }
    }
}

impl Config {
    /// Airtime of a payload of `bytes` bytes, seconds.
    pub fn airtime_s(&self, bytes: usize) -> f64 {
        self.overhead_s + 8.0 * bytes as f64 / self.bit_rate_bps
    }
}

/// The receiver's fix of the sender.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Usbl {
    /// Slant range, metres (noisy, never negative).
    pub range_m: f64,
    /// Bearing of the sender from the receiver, degrees clockwise from north in [0, 360).
    pub azimuth_deg: f64,
    /// Angle of the sender above the receiver's horizontal plane, degrees (positive: the
    /// sender is shallower).
    pub elevation_deg: f64,
}

/// A packet received whole.
#[derive(Debug, Clone, PartialEq)]
pub struct Reception {
    /// The receiver.
    pub to: NodeId,
    /// The sender.
    pub from: NodeId,
    /// The payload (shared by every receiver of the packet).
    pub payload: Arc<[u8]>,
    /// When it was sent.
    pub sent_s: f64,
    /// When its last bit arrived.
    pub arrival_s: f64,
    /// The true slant range at sending, metres.
    pub true_range_m: f64,
    /// The receiver's noisy fix of the sender.
    pub usbl: Usbl,
}

/// Why a transmission was refused.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TxError {
    /// No such node.
    #[error("no node {0:?}")]
    UnknownNode(NodeId),
    /// The payload is over `max_payload`.
    #[error("{bytes} bytes is over the {max}-byte limit")]
    TooLong {
        /// The payload's size.
        bytes: usize,
        /// The limit.
        max: usize,
    },
    /// The node is still transmitting until `until_s`.
    #[error("busy transmitting until {until_s}")]
    Busy {
        /// When its current transmission ends.
        until_s: f64,
    },
    /// The time is before the last step.
    #[error("time {t} is before the last step {now}")]
    TimeWentBack {
        /// The time given.
        t: f64,
        /// The last step's time.
        now: f64,
    },
}

/// What happened to the packets so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Transmissions accepted.
    pub transmitted: u64,
    /// (sender, receiver) pairs beyond the maximum range.
    pub out_of_range: u64,
    /// Arrivals resolved (within range, complete).
    pub arrivals: u64,
    /// Arrivals decoded.
    pub delivered: u64,
    /// Arrivals lost because the receiver was transmitting.
    pub half_duplex: u64,
    /// Arrivals lost in a collision with another arrival.
    pub collisions: u64,
    /// Arrivals lost to the range and size curve.
    pub lost: u64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum BusyKind {
    /// The node's own transmission.
    Tx,
    /// An arrival, by its id.
    Rx(u64),
}

#[derive(Debug, Clone, Copy)]
struct Busy {
    start: f64,
    end: f64,
    kind: BusyKind,
}

#[derive(Debug, Clone)]
struct Arrival {
    id: u64,
    to: NodeId,
    from: NodeId,
    payload: Arc<[u8]>,
    sent_s: f64,
    start: f64,
    end: f64,
    true_range_m: f64,
    decoded: bool,
    usbl: Usbl,
}

#[derive(Debug, Clone)]
struct Node {
    position: Position,
    tx_until: f64,
    busy: Vec<Busy>,
}

/// The channel: nodes, packets in flight, the random stream and the counters.
#[derive(Debug, Clone)]
pub struct Channel {
    config: Config,
    nodes: Vec<Node>,
    pending: Vec<Arrival>,
    now: f64,
    next_id: u64,
    rng: SplitMix64,
    stats: Stats,
}

impl Channel {
    /// An empty channel.
    pub fn new(config: Config) -> Self {
        let rng = SplitMix64(config.seed);
        Self {
            config,
            nodes: Vec::new(),
            pending: Vec::new(),
            now: f64::NEG_INFINITY,
            next_id: 0,
            rng,
            stats: Stats::default(),
        }
    }

    /// The parameters.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The counters.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Packets still in flight (one per receiver within range).
    pub fn in_flight(&self) -> usize {
        self.pending.len()
    }

    /// Adds a node at `position`.
    pub fn add_node(&mut self, position: Position) -> NodeId {
        self.nodes.push(Node {
            position,
            tx_until: f64::NEG_INFINITY,
            busy: Vec::new(),
        });
        NodeId(self.nodes.len() - 1)
    }

    /// Moves `node` (its position from now on; packets in flight keep the geometry they were
    /// sent with).
    pub fn set_position(&mut self, node: NodeId, position: Position) -> Result<(), TxError> {
        let n = self
            .nodes
            .get_mut(node.0)
            .ok_or(TxError::UnknownNode(node))?;
        n.position = position;
        Ok(())
    }

    /// The position of `node`.
    pub fn position(&self, node: NodeId) -> Option<Position> {
        self.nodes.get(node.0).map(|n| n.position)
    }

    /// Sends `payload` from `from` at time `t`; returns when its transmission ends.
    pub fn transmit(&mut self, from: NodeId, payload: &[u8], t: f64) -> Result<f64, TxError> {
        if t < self.now {
            return Err(TxError::TimeWentBack { t, now: self.now });
        }
        let sender = self.nodes.get(from.0).ok_or(TxError::UnknownNode(from))?;
        if payload.len() > self.config.max_payload {
            return Err(TxError::TooLong {
                bytes: payload.len(),
                max: self.config.max_payload,
            });
        }
        if sender.tx_until > t {
            return Err(TxError::Busy {
                until_s: sender.tx_until,
            });
        }
        let here = sender.position;
        let airtime = self.config.airtime_s(payload.len());
        let end = t + airtime;
        let shared: Arc<[u8]> = Arc::from(payload);
        self.stats.transmitted += 1;
        {
            let s = &mut self.nodes[from.0];
            s.tx_until = end;
            s.busy.push(Busy {
                start: t,
                end,
                kind: BusyKind::Tx,
            });
        }
        for to in 0..self.nodes.len() {
            if to == from.0 {
                continue;
            }
            let there = self.nodes[to].position;
            let d = here.distance(&there);
            if d.is_nan() || d > self.config.max_range_m {
                self.stats.out_of_range += 1;
                continue;
            }
            // The draws, the same for every node in range whatever the outcome.
            let u = self.rng.uniform();
            let (n_az, n_el, n_r) = (self.rng.normal(), self.rng.normal(), self.rng.normal());
            let decoded = u < self.config.loss.success(d, payload.len());
            let usbl = self.fix(&there, &here, d, n_az, n_el, n_r);
            let start = t + d / self.config.sound_speed_mps;
            let id = self.next_id;
            self.next_id += 1;
            self.nodes[to].busy.push(Busy {
                start,
                end: start + airtime,
                kind: BusyKind::Rx(id),
            });
            self.pending.push(Arrival {
                id,
                to: NodeId(to),
                from,
                payload: shared.clone(),
                sent_s: t,
                start,
                end: start + airtime,
                true_range_m: d,
                decoded,
                usbl,
            });
        }
        Ok(end)
    }

    /// The noisy fix of a sender at `there` seen from `here`.
    fn fix(
        &self,
        here: &Position,
        there: &Position,
        d: f64,
        n_az: f64,
        n_el: f64,
        n_r: f64,
    ) -> Usbl {
        let (dx, dy) = (there.x_m - here.x_m, there.y_m - here.y_m);
        let up = here.depth_m - there.depth_m;
        let horizontal = dx.hypot(dy);
        let noise = &self.config.usbl;
        let az = dx.atan2(dy).to_degrees() + noise.azimuth_sigma_deg * n_az;
        let el = up.atan2(horizontal).to_degrees() + noise.elevation_sigma_deg * n_el;
        Usbl {
            range_m: (d + noise.range_sigma_m * n_r).max(0.0),
            azimuth_deg: az.rem_euclid(360.0),
            elevation_deg: el.clamp(-90.0, 90.0),
        }
    }

    /// Advances to `t` (never back: an earlier time changes nothing) and returns the packets
    /// received whole by then, by arrival time, then receiver, then sender.
    pub fn step(&mut self, t: f64) -> Vec<Reception> {
        if t > self.now {
            self.now = t;
        }
        let now = self.now;
        let mut out = Vec::new();
        let mut k = 0;
        while k < self.pending.len() {
            if self.pending[k].end > now {
                k += 1;
                continue;
            }
            let a = self.pending.swap_remove(k);
            self.stats.arrivals += 1;
            let overlaps = |b: &Busy| b.start < a.end && a.start < b.end;
            let busy = &self.nodes[a.to.0].busy;
            if busy.iter().any(|b| b.kind == BusyKind::Tx && overlaps(b)) {
                self.stats.half_duplex += 1;
            } else if busy
                .iter()
                .any(|b| matches!(b.kind, BusyKind::Rx(id) if id != a.id) && overlaps(b))
            {
                self.stats.collisions += 1;
            } else if !a.decoded {
                self.stats.lost += 1;
            } else {
                self.stats.delivered += 1;
                out.push(Reception {
                    to: a.to,
                    from: a.from,
                    payload: a.payload,
                    sent_s: a.sent_s,
                    arrival_s: a.end,
                    true_range_m: a.true_range_m,
                    usbl: a.usbl,
                });
            }
        }
        // A busy interval matters while an unresolved arrival could overlap it: drop those
        // that end before every pending arrival starts (and before now).
        let horizon = self.pending.iter().map(|a| a.start).fold(now, f64::min);
        for n in &mut self.nodes {
            n.busy.retain(|b| b.end >= horizon);
        }
        out.sort_by(|a, b| {
            a.arrival_s
                .total_cmp(&b.arrival_s)
                .then(a.to.cmp(&b.to))
                .then(a.from.cmp(&b.from))
                .then(a.sent_s.total_cmp(&b.sent_s))
        });
        out
    }
}

/// SplitMix64 (Steele, Lea and Flood), small and fixed forever, so a seed's stream never
/// changes with a dependency's version.
#[derive(Debug, Clone)]
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller, one of the pair).
    fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}
