//! BHV_PModelView on the helm's Dubins platform model (MOOS-IvP a2a9b716
//! `BHV_PModelView::drawTurnPath` with `PlatModel::getTurnSeglr` and `XYSeglr::get_spec`):
//! the turn's spokes after ownship's position, then the ray.

use behaviors::plat_model::PlatModel;
use behaviors::{Ctx, Emit, MapInfo, Out, Value};
use ivp::Domain;

#[test]
fn the_view_draws_the_dubins_turn() {
    let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    // North at the origin, radius 20, a spoke every 90°: the turn to 90 passes (20, 20).
    let info = MapInfo::new(5.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0)
        .num("DESIRED_HEADING", 90.0)
        .num("DESIRED_SPEED", 2.0)
        .with_plat_model(PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 20.0, 90.0));
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "pv",
        perpetual: false,
    };
    let mut b = behaviors::create("BHV_PModelView").unwrap();
    let mut out = Out::default();
    assert!(b.on_run(&ctx, &mut out).is_none());
    let seglr = out.emits.iter().find_map(|e| match e {
        Emit::Post { var, value, .. } if var == "VIEW_SEGLR" => Some(value.clone()),
        _ => None,
    });
    assert_eq!(
        seglr,
        Some(Value::text(
            "pts={0.0,0.0:20.0,20.0},ray=90.0,label=abe_seglr,vertex_color=lime_green,\
             vertex_size=2,ray_len=20,head_size=1"
        ))
    );
}
