//! `BHV_ABLE_FILTER` for BHV_AvoidObstacleV24 (MOOS `BHV_AvoidObstacleV24::applyAbleFilter`
//! at a2a9b716): with `can_disable = true` (false by default, IvPBehavior's), a message
//! `action=disable|enable|expunge` with `obstacle_id=<id>` or `vsource=<source>`
//! (comma-separated `field=value`, case-folded, each field once) disables or enables the
//! behaviour when the id (or, without an id, the obstacle polygon's `vsource`) matches;
//! `expunge` enables and completes it. Any other field, or neither `obstacle_id` nor
//! `vsource`, is malformed. Disabled, the behaviour builds no function; its every-state
//! work (the obstacle manager's resolutions, the model) goes on, as the C++ `onEveryState`
//! runs in every state.

use crate::contact::{AbleAction, MalformedAbleFilter};

use super::ObstacleBase;

impl ObstacleBase {
    /// Applies a `BHV_ABLE_FILTER` message (see the module docs); `Ok(Some(action))` when it
    /// applied to this behaviour.
    pub fn apply_able_filter(
        &mut self,
        msg: &str,
    ) -> Result<Option<AbleAction>, MalformedAbleFilter> {
        if !self.can_disable {
            return Ok(None);
        }
        let (mut action, mut obid, mut vsource) = (String::new(), String::new(), String::new());
        for piece in moos_types::text::parse_string(msg, ',') {
            let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim().to_ascii_lowercase());
            let slot = match k.as_str() {
                "action" => &mut action,
                "obstacle_id" => &mut obid,
                "vsource" => &mut vsource,
                _ => return Err(MalformedAbleFilter),
            };
            if !slot.is_empty() {
                return Err(MalformedAbleFilter);
            }
            *slot = v;
        }
        let act = match action.as_str() {
            "disable" => AbleAction::Disable,
            "enable" => AbleAction::Enable,
            "expunge" => AbleAction::Expunge,
            _ => return Err(MalformedAbleFilter),
        };
        if !obid.is_empty() {
            if obid != self.obstacle_id.to_ascii_lowercase() {
                return Ok(None);
            }
        } else if !vsource.is_empty() {
            let poly_vsource = self.poly.as_ref().map_or("", |p| p.attrs.vsource.as_str());
            if vsource != poly_vsource.to_ascii_lowercase() {
                return Ok(None);
            }
        } else {
            return Err(MalformedAbleFilter);
        }
        self.disabled = act == AbleAction::Disable;
        Ok(Some(act))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filter_matches_the_obstacle_id_or_the_polygons_vsource() {
        let mut b = ObstacleBase::new();
        b.obstacle_id = "Ob_3".into();
        b.set_poly("pts={0,0:10,0:10,10},label=ob_3,vsource=Radar")
            .unwrap();
        assert_eq!(b.apply_able_filter("action=disable,gen_type=x"), Ok(None));
        assert!(!b.disabled, "can_disable is false by default");
        b.can_disable = true;
        for bad in [
            "action=disable",
            "action=disable,contact=ob_3",
            "action=able,obstacle_id=ob_3",
            "action=disable,obstacle_id=ob_3,obstacle_id=ob_4",
        ] {
            assert_eq!(b.apply_able_filter(bad), Err(MalformedAbleFilter), "{bad}");
        }
        assert_eq!(
            b.apply_able_filter("action=disable,obstacle_id=ob_4"),
            Ok(None)
        );
        assert_eq!(
            b.apply_able_filter("action=disable, obstacle_id=OB_3"),
            Ok(Some(AbleAction::Disable))
        );
        assert!(b.disabled);
        assert_eq!(b.apply_able_filter("action=enable,vsource=ais"), Ok(None));
        assert_eq!(
            b.apply_able_filter("action=enable,vsource=radar"),
            Ok(Some(AbleAction::Enable))
        );
        assert!(!b.disabled);
        b.disabled = true;
        assert_eq!(
            b.apply_able_filter("action=expunge,obstacle_id=ob_3"),
            Ok(Some(AbleAction::Expunge))
        );
        assert!(!b.disabled, "expunge enables (and completes)");
    }
}
