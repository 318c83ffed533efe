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
