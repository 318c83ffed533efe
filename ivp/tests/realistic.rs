//! The benchmark problems (helm-sized domains) solved exactly: the solver's optimum equals a
//! brute-force maximum over every grid point, and the chosen point attains it.

#[path = "../benches/common/mod.rs"]
mod common;

use ivp::{Domain, IvpFunction, Problem, Solver};

/// Per-function value tables over the function's own grid (`None` where uncovered), with the
/// solver's normalization rule and priority weight applied.
fn table(f: &IvpFunction) -> Vec<Option<f64>> {
    let mut g = f.clone();
    if g.max_val() - g.min_val() > 100.0 {
        g.normalize(0.0, 100.0);
    }
    let pts: Vec<u32> = g.domain().vars().iter().map(|v| v.points()).collect();
    let total: usize = pts.iter().map(|&p| p as usize).product();
    let mut out = vec![None; total];
    for p in g.pieces() {
        // walk every grid point of the piece
        let d = pts.len();
        let mut ix = p.lo.to_vec();
        'points: loop {
            let flat = (0..d).fold(0usize, |acc, k| acc * pts[k] as usize + ix[k] as usize);
            if out[flat].is_none() {
                out[flat] = Some(f.pwt() * p.eval(&ix));
            }
            let mut k = d;
            loop {
                if k == 0 {
                    break 'points;
                }
                k -= 1;
                if ix[k] < p.hi[k] {
                    ix[k] += 1;
                    continue 'points;
                }
                ix[k] = p.lo[k];
            }
        }
    }
    out
}

/// A function's variables (as helm-domain positions), its own grid sizes, and its values.
type Table = (Vec<usize>, Vec<u32>, Vec<Option<f64>>);

fn brute_force(problem: &Problem) -> (f64, usize) {
    let domain: &Domain = problem.domain();
    let pts: Vec<u32> = domain.vars().iter().map(|v| v.points()).collect();
    let tables: Vec<Table> = problem
        .functions()
        .map(|(_, f)| {
            let map = f
                .domain()
                .vars()
                .iter()
                .map(|v| domain.index_of(v.name()).unwrap())
                .collect();
            let own = f.domain().vars().iter().map(|v| v.points()).collect();
            (map, own, table(f))
        })
        .collect();
    let total: usize = pts.iter().map(|&p| p as usize).product();
    let mut best = f64::NEG_INFINITY;
    let mut ix = vec![0u32; pts.len()];
    let mut covered_points = 0;
    for flat in 0..total {
        let mut rem = flat;
        for k in (0..pts.len()).rev() {
            ix[k] = (rem % pts[k] as usize) as u32;
            rem /= pts[k] as usize;
        }
        let mut sum = 0.0;
        let mut ok = true;
        for (map, own, t) in &tables {
            let f_flat = map
                .iter()
                .zip(own)
                .fold(0usize, |acc, (&m, &p)| acc * p as usize + ix[m] as usize);
            match t[f_flat] {
                Some(v) => sum += v,
                None => {
                    ok = false;
                    break;
                }
            }
        }
        if ok {
            covered_points += 1;
            best = best.max(sum);
        }
    }
    (best, covered_points)
}

fn check(problem: &Problem) {
    let (best, covered) = brute_force(problem);
    assert!(covered > 0);
    let dec = Solver::new().solve(problem).expect("a decision");
    let tol = 1e-9 * best.abs().max(1.0);
    assert!(
        (dec.value - best).abs() <= tol,
        "solver {} brute force {}",
        dec.value,
        best
    );
    // evaluate the collective objective at the chosen point
    let mut at = 0.0;
    for (_, f) in problem.functions() {
        let own: Vec<u32> = f
            .domain()
            .vars()
            .iter()
            .map(|v| dec.vars.iter().find(|d| d.name == v.name()).unwrap().index)
            .collect();
        let mut g = f.clone();
        if g.max_val() - g.min_val() > 100.0 {
            g.normalize(0.0, 100.0);
        }
        at += f.pwt() * g.eval(&own).unwrap();
    }
    assert!(
        (at - best).abs() <= tol,
        "value at the decision {at} vs optimum {best}"
    );
}

#[test]
fn course_speed_problem_is_solved_exactly() {
    check(&common::problem_a());
}

#[test]
fn course_speed_depth_problem_is_solved_exactly() {
    check(&common::problem_b());
}
