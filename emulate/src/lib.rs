//! Device emulators of the CougUV (issue #15, part 2): the GPS (NMEA 0183 on a serial line,
//! gpsd's JSON on TCP), the Water Linked DVL A50 (JSON on TCP), the SeaTrac X150 (ASCII-hex
//! frames on a serial line) and the Teensy (ASCII lines on a serial line), each serving the
//! exact wire protocol of `cougars-vehicle.md` §3 through the codecs of the `devices` crate,
//! so the drivers cannot tell them from the hardware.
//!
//! Each emulator has a pure part and an I/O edge:
//! - [`device::Device`]: time, truth and faults in, bytes out; bytes in, state changes and
//!   answers out. One per device: [`gps::NmeaGps`], [`gps::Gpsd`], [`dvl::A50`],
//!   [`seatrac::X150`], [`teensy::Teensy`].
//! - [`device::Emulator`]: a device with its [`truth::TruthSource`] (the simulator's feed,
//!   [`truth::SharedTruth`], or the built-in [`truth::BoxScenario`]) and its
//!   [`fault::FaultPlan`] (noise bursts, dropouts, disconnections, garbage bytes, a leak, a
//!   falling battery), every draw from one seed.
//! - [`transport`]: the edge, on a tokio runtime: a TCP listener on 127.0.0.1 or a
//!   pseudo-terminal ([`pty`]) whose slave a serial driver opens like a device (optionally
//!   through a symbolic link), ticking the emulator on tokio's clock (paused in tests);
//!   [`transport::spawn`] runs one in process and returns its endpoint and a handle to stop
//!   it and feed it truth; `coug emulate` runs one until Ctrl-C.
//! - [`build`]: one emulator by device name with its options, shared by the CLI and tests;
//!   [`build::spawn_warped`] runs it on a clock warped as the community's ([`warp`]).
//!
//! In process, beside the simulator (or in a driver's test):
//!
//! ```
//! use emulate::build::{self, Kind, Options, Settings};
//! use emulate::transport::Transport;
//! use emulate::truth::Truth;
//! use tokio::io::AsyncBufReadExt;
//!
//! # tokio::runtime::Runtime::new().unwrap().block_on(async {
//! let dvl = build::spawn(Kind::Dvl, Settings::default(), Transport::loopback(0), Options::default())
//!     .await
//!     .unwrap();
//! dvl.truth.feed(Truth { depth: 5.0, vel_north_mps: 1.0, ..Truth::default() });
//! let addr = dvl.handle.endpoint().tcp().unwrap();
//! let stream = tokio::net::TcpStream::connect(addr).await.unwrap();
//! let line = tokio::io::BufReader::new(stream).lines().next_line().await.unwrap().unwrap();
//! assert!(devices::a50::parse(line.as_bytes()).is_ok());
//! dvl.handle.stop().await.unwrap();
//! # });
//! ```

#![warn(missing_docs)]

pub mod build;
pub mod device;
pub mod dvl;
pub mod fault;
pub mod gps;
pub mod pty;
pub mod seatrac;
pub mod teensy;
pub mod transport;
pub mod truth;
pub mod warp;
