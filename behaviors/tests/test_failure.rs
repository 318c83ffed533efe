//! BHV_TestFailure as MOOS-IvP a2a9b716: the failure type and what completion does.

mod support;

use behaviors::{Fault, ParamError};
use support::{Bhv, uuv_domain};

fn fault_on_completion(b: &mut Bhv) -> Option<Fault> {
    let ctx = behaviors::Ctx {
        info: &b.info,
        domain: &b.domain,
        ownship: "abe",
        name: &b.name,
        perpetual: false,
    };
    let mut out = behaviors::Out::default();
    b.bhv.on_complete(&ctx, &mut out);
    out.fault
}

#[test]
fn crash_by_default_burn_or_hang_with_a_time() {
    let mut b = Bhv::new("BHV_TestFailure", "tf", uuv_domain()).config(&[]);
    assert_eq!(b.bhv.default_name(), "test_failure");
    // No objective function, no fault while running.
    let (f, out) = b.run(0.0);
    assert!(f.is_none() && out.fault.is_none() && out.emits.is_empty());
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Crash));
    // burn: 3 s by default.
    b.set("failure_type", "burn").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Burn(3.0)));
    // hang,N (any case, blank ends ignored) sets the time.
    b.set("failure_type", " Hang,7.5 ").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Burn(7.5)));
    // A time that is not a number keeps the previous one.
    b.set("failure_type", "burn,soon").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Burn(7.5)));
    b.set("failure_type", "crash").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Crash));
    // And the burn time survives a crash setting.
    b.set("failure_type", "burnout").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Burn(7.5)));
}

#[test]
fn any_failure_type_text_is_accepted_as_the_cpp_accepts_it() {
    // The C++ setParam returns true for failure_type whatever its value; an unknown one
    // changes nothing.
    let mut b = Bhv::new("BHV_TestFailure", "tf", uuv_domain());
    b.set("failure_type", "explode").unwrap();
    assert_eq!(fault_on_completion(&mut b), Some(Fault::Crash));
    assert!(matches!(
        b.set("burn_time", "3"),
        Err(ParamError::Unknown { .. })
    ));
}
