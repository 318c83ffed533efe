//! `my-coug`: the coug binary with one more behaviour type, BHV_Orbit.
//!
//! ```text
//! cargo run -p my-behaviour -- run examples/my-behaviour/mission/orbit.moos \
//!     --lockstep --deploy --until "MISSION = complete"
//! ```

use behaviors::Registry;
use my_behaviour::Orbit;

fn main() {
    coug::main_with(Registry::with_stock().register("BHV_Orbit", Orbit::new))
}
