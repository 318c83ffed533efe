//! The web viewer behind `coug view` (issue #17): what a browser page draws of a MOOS
//! community, kept from MOOS mail, and the server that hands it to the page.
//!
//! - [`scene`] (pure, time as an argument): vehicles, `VIEW_*` objects, appcasts and the
//!   mission's buttons, and the JSON snapshot/delta messages of the websocket.
//! - [`background`]: pMarineViewer's `tiff_file` background (`.tif` and `.info`), decoded,
//!   placed on the mission's grid and served as PNG.
//! - [`context`]: the mouse context pokes and their macros.
//! - [`live`] and [`replay`]: the viewer beside an in-process run, and over a log.
//! - [`server`]: the axum router (the embedded page, `/ws`, button presses), the access rules
//!   (loopback by default, a token otherwise), and the MOOS side (`join`: a client that feeds
//!   the scene and posts button presses).
#![warn(missing_docs)]

pub mod background;
pub mod context;
pub mod live;
pub mod replay;
pub mod scene;
pub mod server;
