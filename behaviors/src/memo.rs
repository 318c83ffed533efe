//! The last objective function a behaviour built from its parameters alone (the constant
//! speed, depth and heading behaviours, BHV_MaxDepth): while the parameters and the helm's
//! domain are the same, the helm gets a copy of it instead of a new ZAIC build each iteration.

use ivp::{Domain, IvpFunction, ZaicPeak};

/// A function and the inputs it was built from: the domain and `N` parameters, compared by
/// their bits (so a parameter that changes in any way rebuilds it).
#[derive(Debug, Clone)]
pub(crate) struct FnMemo<const N: usize> {
    last: Option<(Domain, [u64; N], IvpFunction)>,
}

impl<const N: usize> Default for FnMemo<N> {
    fn default() -> Self {
        FnMemo { last: None }
    }
}

impl<const N: usize> FnMemo<N> {
    /// The function built from `domain` and `params`, made by `build` unless it was the last
    /// one built; a failed build is not kept (its errors are reported every time).
    pub(crate) fn get_or<E>(
        &mut self,
        domain: &Domain,
        params: [f64; N],
        build: impl FnOnce() -> Result<IvpFunction, E>,
    ) -> Result<IvpFunction, E> {
        let bits = params.map(f64::to_bits);
        if let Some((d, p, f)) = &self.last
            && *p == bits
            && d == domain
        {
            return Ok(f.clone());
        }
        let f = build()?;
        self.last = Some((domain.clone(), bits, f.clone()));
        Ok(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_function_is_built_again_only_when_an_input_changes() {
        let d = Domain::parse_specs(["speed:0:4:41"]).unwrap();
        let other = Domain::parse_specs(["speed:0:5:51"]).unwrap();
        let mut m = FnMemo::<1>::default();
        let mut builds = 0;
        let mut get = |m: &mut FnMemo<1>, d: &Domain, x: f64| {
            m.get_or(d, [x], || {
                builds += 1;
                Ok::<_, ()>(IvpFunction::new(d.clone()))
            })
            .unwrap()
        };
        assert_eq!(get(&mut m, &d, 1.0).domain(), &d);
        get(&mut m, &d, 1.0);
        get(&mut m, &d, -0.0);
        get(&mut m, &d, 0.0);
        assert_eq!(get(&mut m, &other, 0.0).domain(), &other);
        assert_eq!(builds, 4, "1.0 once, -0 and 0 apart, the other domain");
        let mut fails = FnMemo::<1>::default();
        assert!(fails.get_or(&d, [1.0], || Err("no")).is_err());
        assert!(fails.last.is_none(), "a failure is not kept");
    }
}

/// Why [`FnMemo::peak`] built no function.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PeakError {
    /// The helm's domain has no such variable.
    NoVariable,
    /// The ZAIC refused its parameters or could not be extracted (its message).
    Refused(String),
}

impl FnMemo<4> {
    /// The peak ZAIC over domain variable `var` (wrapping round its range when `wrap`, as a
    /// course does) from `[value, peakwidth, basewidth, summitdelta]`, minimum utility 0 and
    /// maximum 100: the function of the constant speed, depth and heading behaviours, kept
    /// while its inputs are the same.
    pub(crate) fn peak(
        &mut self,
        domain: &Domain,
        var: &str,
        wrap: bool,
        params: [f64; 4],
    ) -> Result<IvpFunction, PeakError> {
        self.get_or(domain, params, || {
            let mut z = ZaicPeak::new(domain, var).map_err(|_| PeakError::NoVariable)?;
            z.set_value_wrap(wrap);
            let [value, peak, base, delta] = params;
            z.set_params(value, peak, base, delta, 0.0, 100.0)
                .map_err(|e| PeakError::Refused(e.to_string()))?;
            z.extract().map_err(|e| PeakError::Refused(e.to_string()))
        })
    }
}
