//! Round trip: generated files are printed in canonical form, parsed, printed and parsed again;
//! the ASTs must match (and the parsed conditions must equal the generated ones).

use mission::Param;
use mission::bhv::{BehaviorFile, BehaviorSpec, ConditionEntry, Initialize, ModeBlock, parse_bhv};
use mission::condition::{Condition, Operand, RelOp, moos_compat, parse_condition};
use mission::moos::{MissionFile, ProcessConfig, parse_moos};
use mission::source::{SourceMap, Span};
use proptest::prelude::*;

fn span() -> Span {
    Span::new("generated", 1, 1)
}

fn var() -> impl Strategy<Value = String> {
    "[A-Z][A-Z0-9_]{0,7}".prop_filter("not a keyword", |s| {
        !["AND", "OR", "NOT"].contains(&s.as_str())
    })
}

fn operand() -> impl Strategy<Value = Operand> {
    prop_oneof![
        var().prop_map(Operand::Var),
        "[a-zA-Z0-9_:. -]{0,10}".prop_map(Operand::Str),
        (-1_000_000i64..1_000_000, 0u32..4)
            .prop_map(|(m, e)| Operand::Num(m as f64 / 10f64.powi(e as i32))),
    ]
}

fn op(allow_field: bool) -> impl Strategy<Value = RelOp> {
    let ops = if allow_field {
        vec![
            RelOp::Eq,
            RelOp::FieldEq,
            RelOp::Ne,
            RelOp::Lt,
            RelOp::Le,
            RelOp::Gt,
            RelOp::Ge,
        ]
    } else {
        vec![
            RelOp::Eq,
            RelOp::Ne,
            RelOp::Lt,
            RelOp::Le,
            RelOp::Gt,
            RelOp::Ge,
        ]
    };
    prop::sample::select(ops)
}

fn condition(allow_field: bool) -> impl Strategy<Value = Condition> {
    let leaf = (var(), op(allow_field), operand()).prop_map(|(v, op, rhs)| Condition::Compare {
        lhs: Operand::Var(v),
        op,
        rhs,
    });
    leaf.prop_recursive(4, 16, 3, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 2..4).prop_map(Condition::And),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Condition::Or),
            inner.prop_map(|c| Condition::Not(Box::new(c))),
        ]
    })
}

fn key() -> impl Strategy<Value = String> {
    "[a-z][a-z_]{0,10}".prop_filter("not a keyword", |k| {
        !["set", "behavior", "initialize", "initialize_", "condition"].contains(&k.as_str())
    })
}

fn value() -> impl Strategy<Value = String> {
    "[a-zA-Z0-9_,:=.$()\\[\\]@~# -]{0,24}"
        .prop_map(|v| v.trim().to_string())
        .prop_filter("no comment, no brace at the ends", |v| {
            !v.contains("//") && !v.starts_with('#')
        })
}

fn cond_entry(allow_field: bool) -> impl Strategy<Value = ConditionEntry> {
    condition(allow_field).prop_map(|c| ConditionEntry {
        text: c.to_string(),
        condition: c,
        span: span(),
    })
}

fn behavior() -> impl Strategy<Value = BehaviorSpec> {
    (
        "BHV_[A-Za-z]{1,10}",
        prop::collection::vec((key(), value()), 0..6),
        prop::collection::vec(cond_entry(true), 0..3),
    )
        .prop_map(|(kind, params, conds)| {
            let mut params: Vec<Param> = params
                .into_iter()
                .map(|(key, value)| Param {
                    key,
                    value,
                    span: span(),
                })
                .collect();
            for c in &conds {
                params.push(Param {
                    key: "condition".into(),
                    value: c.text.clone(),
                    span: span(),
                });
            }
            BehaviorSpec {
                kind,
                params,
                conditions: conds,
                span: span(),
            }
        })
}

fn mode() -> impl Strategy<Value = ModeBlock> {
    (
        var(),
        var(),
        prop::collection::vec(cond_entry(false), 0..3),
        prop::option::of(var()),
    )
        .prop_map(|(var, value, conditions, else_value)| ModeBlock {
            var,
            value,
            conditions,
            else_value,
            span: span(),
        })
}

fn init() -> impl Strategy<Value = Initialize> {
    (var(), "[a-zA-Z0-9_.:-]{1,10}", any::<bool>()).prop_map(|(var, value, deferred)| Initialize {
        var,
        value,
        deferred,
        span: span(),
    })
}

fn bhv_file() -> impl Strategy<Value = BehaviorFile> {
    (
        prop::collection::vec(init(), 0..4),
        prop::collection::vec(mode(), 0..4),
        prop::collection::vec(behavior(), 0..4),
    )
        .prop_map(|(initializes, modes, behaviors)| BehaviorFile {
            initializes,
            modes,
            behaviors,
        })
}

fn moos_entry() -> impl Strategy<Value = Param> {
    let gkey = "[A-Za-z][A-Za-z0-9_]{0,10}".prop_filter("not a header", |k| {
        !k.eq_ignore_ascii_case("processconfig") && !k.to_ascii_lowercase().starts_with("define")
    });
    (gkey, value()).prop_map(|(key, value)| Param {
        key,
        value,
        span: span(),
    })
}

fn moos_file() -> impl Strategy<Value = MissionFile> {
    let block = (
        "[A-Za-z][A-Za-z0-9_]{0,10}",
        prop::collection::vec(moos_entry(), 0..6),
    )
        .prop_map(|(name, entries)| ProcessConfig {
            name,
            span: span(),
            entries,
        });
    (
        prop::collection::vec(moos_entry(), 0..5),
        prop::collection::vec(block, 0..4),
    )
        .prop_map(|(globals, processes)| MissionFile {
            globals,
            processes,
            defines: vec![],
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn condition_print_parse_is_identity(c in condition(true)) {
        let printed = c.to_string();
        let back = parse_condition(&printed);
        prop_assert_eq!(back.as_ref(), Ok(&c), "printed: {}", printed);
        // The canonical form is one pHelmIvP accepts too.
        prop_assert!(moos_compat(&printed).is_none(), "printed: {}", printed);
    }

    #[test]
    fn bhv_round_trip(generated in bhv_file()) {
        let text = generated.to_string();
        let first = parse_bhv(&SourceMap::from_text("generated.bhv", &text));
        prop_assert!(first.diagnostics.is_empty(), "{:?}\n{}", first.diagnostics, text);
        prop_assert!(generated.same_content(&first.value), "generated and parsed differ:\n{}", text);
        let again_text = first.value.to_string();
        prop_assert_eq!(&again_text, &text);
        let again = parse_bhv(&SourceMap::from_text("generated.bhv", &again_text));
        prop_assert!(first.value.same_content(&again.value));
    }

    #[test]
    fn moos_round_trip(generated in moos_file()) {
        let text = generated.to_string();
        let first = parse_moos(&SourceMap::from_text("generated.moos", &text));
        prop_assert!(first.diagnostics.is_empty(), "{:?}\n{}", first.diagnostics, text);
        prop_assert!(generated.same_content(&first.value), "generated and parsed differ:\n{}", text);
        let again = parse_moos(&SourceMap::from_text("generated.moos", &first.value.to_string()));
        prop_assert!(first.value.same_content(&again.value));
    }
}

#[test]
fn corpus_like_file_round_trips() {
    let text = "initialize DEPLOY = false, RETURN = false\ninitialize_ SPD = 2\n\
                set MODE = ACTIVE {\n DEPLOY = true\n}\nINACTIVE\n\
                Behavior = BHV_Waypoint {\n  condition = MODE==ACTIVE\n  condition = (A=1) and ((B<2) or !(C=\"x y\"))\n  points = 0,0:10,10 \\\n   :20,20\n}\n";
    let first = parse_bhv(&SourceMap::from_text("c.bhv", text));
    assert!(first.diagnostics.is_empty(), "{:?}", first.diagnostics);
    assert_eq!(first.value.initializes.len(), 3);
    assert!(first.value.initializes[2].deferred);
    assert_eq!(first.value.modes[0].else_value.as_deref(), Some("INACTIVE"));
    assert_eq!(
        first.value.behaviors[0].get("points"),
        Some("0,0:10,10 :20,20")
    );
    let printed = first.value.to_string();
    let second = parse_bhv(&SourceMap::from_text("c.bhv", &printed));
    assert!(second.diagnostics.is_empty());
    assert!(first.value.same_content(&second.value), "{printed}");
    assert_eq!(
        second.value.behaviors[0].conditions[1]
            .condition
            .to_string(),
        "(A = 1) and ((B < 2) or !(C = \"x y\"))"
    );
}
