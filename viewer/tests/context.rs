//! Mouse context pokes server-side: only the mission's configured `left_context`/
//! `right_context` postings are ever posted, with the click's macros expanded.

use std::sync::{Arc, Mutex};

use moos_types::Value;
use viewer::context::{Side, context_pokes};
use viewer::server::{Outbox, Viewer, ViewerConfig};

#[derive(Default)]
struct Recorder(Mutex<Vec<(String, Value)>>);

impl Outbox for Recorder {
    fn post(&self, var: &str, value: Value) -> Result<(), String> {
        self.0.lock().unwrap().push((var.to_string(), value));
        Ok(())
    }
    fn moos_time(&self) -> f64 {
        500.0
    }
}

#[test]
fn only_configured_context_pokes_are_posted() {
    let src = mission::source::SourceMap::from_text(
        "m.moos",
        "ProcessConfig = pMarineViewer\n{\n  \
         right_context[goto] = GOTO_$(UP_VNAME) = x=$(XPOS),y=$(YPOS),hdg=$(HDG)\n  \
         right_context[goto] = DEPLOY_$(UP_VNAME) = true\n  \
         left_context[mark] = MARK = $(X),$(Y)\n}\n",
    );
    let m = mission::moos::parse_moos(&src).value;
    let rec = Arc::new(Recorder::default());
    let config = ViewerConfig {
        contexts: context_pokes(&m),
        ..ViewerConfig::default()
    };
    let v = Viewer::new(&config, rec.clone()).unwrap();
    v.apply("NODE_REPORT", "NAME=abe,X=0,Y=0,HDG=0,SPD=0,TIME=1", 1.0);
    // Unknown key, or a key of the other side: refused, nothing posted.
    assert!(v.click(Side::Right, "DEPLOY", 1.0, 1.0, "abe").is_err());
    assert!(v.click(Side::Right, "mark", 1.0, 1.0, "abe").is_err());
    assert!(v.click(Side::Left, "goto", 1.0, 1.0, "abe").is_err());
    assert!(rec.0.lock().unwrap().is_empty());
    // The configured one: both its postings, macros expanded.
    let posts = v.click(Side::Right, "goto", 10.0, 10.04, "abe").unwrap();
    assert_eq!(
        posts,
        vec![
            ("GOTO_ABE".to_string(), Value::text("x=10,y=10,hdg=45.00")),
            ("DEPLOY_ABE".to_string(), Value::text("true")),
        ]
    );
    assert_eq!(*rec.0.lock().unwrap(), posts);
    let left = v.click(Side::Left, "mark", -3.6, 2.2, "").unwrap();
    assert_eq!(left, vec![("MARK".to_string(), Value::text("-4,2"))]);
}

fn viewer_for(text: &str) -> (Arc<Viewer>, Arc<Recorder>) {
    let src = mission::source::SourceMap::from_text("m.moos", text);
    let m = mission::moos::parse_moos(&src).value;
    let rec = Arc::new(Recorder::default());
    let v = Viewer::new(&ViewerConfig::for_mission(&m), rec.clone()).unwrap();
    (v, rec)
}

const MARK: &str = "ProcessConfig = pMarineViewer\n{\n  \
     left_context[mark] = MARK_$(UP_VNAME_CLOSEST) = lat=$(LAT),lon=$(LON),near=$(VNAME_CLOSEST)\n}\n";

#[test]
fn lat_lon_are_the_click_on_the_missions_grid() {
    let (v, rec) = viewer_for(&format!(
        "LatOrigin = 43.825300\nLongOrigin = -70.330400\n{MARK}"
    ));
    v.apply("NODE_REPORT", "NAME=abe,X=0,Y=0,TIME=1", 1.0);
    v.apply("NODE_REPORT", "NAME=ben,X=200,Y=-90,TIME=1", 1.0);
    let posts = v.click(Side::Left, "mark", 150.04, -80.0, "abe").unwrap();
    assert_eq!(posts.len(), 1);
    assert_eq!(posts[0].0, "MARK_BEN", "ben is nearest the click");
    let text = posts[0].1.as_str().unwrap().to_string();
    let field = |k: &str| -> f64 {
        text.split(',')
            .find_map(|p| p.strip_prefix(k))
            .unwrap_or_else(|| panic!("{k} in {text}"))
            .parse()
            .unwrap()
    };
    let (lat, lon) = (field("lat="), field("lon="));
    // Eight decimals, and back on the grid at the click snapped to 0.1 m (1e-8 degrees is
    // about a millimetre).
    let decimals = |k: &str| text.split(k).nth(1).unwrap().split([',']).next().unwrap();
    assert_eq!(
        decimals("lat=").split('.').nth(1).unwrap().len(),
        8,
        "{text}"
    );
    let grid = vehicle::geodesy::LocalGrid::new(43.8253, -70.3304).unwrap();
    let (x, y) = grid.to_local(lat, lon).unwrap();
    assert!(
        (x - 150.0).abs() < 0.01 && (y + 80.0).abs() < 0.01,
        "{x} {y}"
    );
    assert!(text.ends_with(",near=ben"), "{text}");
    assert_eq!(rec.0.lock().unwrap().len(), 1);
}

#[test]
fn lat_lon_without_an_origin_post_nothing() {
    let (v, rec) = viewer_for(MARK);
    let err = v.click(Side::Left, "mark", 1.0, 2.0, "").unwrap_err();
    assert_eq!(err, viewer::server::PressError::NoOrigin);
    assert!(rec.0.lock().unwrap().is_empty());
}
