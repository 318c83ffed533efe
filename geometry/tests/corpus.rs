//! Every `points` / `polygon` / `xpoints` / `point` / `station_pt` value in the real MOOS-IvP
//! mission `.bhv` files must parse (values still holding an nsplug `$(MACRO)` are skipped,
//! since the mission's launch script would expand them first).

use geometry::spec::{parse_point, parse_polygon, parse_seglist, parse_waypoints};

#[derive(Default)]
struct Tally {
    parsed: usize,
    skipped_macro: usize,
    seglists: usize,
    polygons: usize,
    points: usize,
    failures: Vec<String>,
}

#[test]
fn every_corpus_geometry_value_parses() {
    let files = test_support::files_with_ext(&test_support::mission_file(""), &["bhv"]);
    assert!(
        files.len() >= 60,
        "expected the 69 corpus .bhv files, found {}",
        files.len()
    );

    let mut t = Tally::default();
    for file in &files {
        let text =
            std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut behavior = String::new();
        for (lineno, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.starts_with("//") || line.starts_with('#') {
                continue;
            }
            let line = line.split("//").next().unwrap_or("").trim();
            let Some((key, value)) = line.split_once('=') else {
                continue;
            };
            let key = key.trim().to_ascii_lowercase();
            let value = value.trim();
            if key == "behavior" || key == "behaviour" {
                behavior = value.to_string();
                continue;
            }
            let kind = match key.as_str() {
                "points" | "xpoints" | "polygon" | "point" | "station_pt" => key.as_str(),
                _ => continue,
            };
            if value.contains("$(") {
                t.skipped_macro += 1;
                continue;
            }
            let is_waypoint = behavior.eq_ignore_ascii_case("BHV_Waypoint");
            let result = match kind {
                "point" | "station_pt" => parse_point(value).map(|_| t.points += 1),
                // The waypoint behaviour reads points/polygon as a seglist, falling back to a
                // polygon exported from the vertex nearest the vehicle.
                _ if is_waypoint => parse_waypoints(value, 0.0, 0.0).map(|v| {
                    assert!(
                        !v.seglist.is_empty(),
                        "{}:{} empty path",
                        file.display(),
                        lineno + 1
                    );
                    t.seglists += 1;
                }),
                "polygon" => parse_polygon(value).map(|v| {
                    assert!(
                        !v.polygon.is_empty(),
                        "{}:{} empty polygon",
                        file.display(),
                        lineno + 1
                    );
                    t.polygons += 1;
                }),
                _ => parse_seglist(value).map(|_| t.seglists += 1),
            };
            match result {
                Ok(()) => t.parsed += 1,
                Err(e) => t.failures.push(format!(
                    "{}:{} [{behavior}] {key} = {value}: {e}",
                    file.display(),
                    lineno + 1
                )),
            }
        }
    }
    println!(
        "corpus geometry values: {} parsed ({} seglists, {} polygons, {} points), {} skipped (unexpanded macros), {} files",
        t.parsed,
        t.seglists,
        t.polygons,
        t.points,
        t.skipped_macro,
        files.len()
    );
    assert!(
        t.failures.is_empty(),
        "corpus values that failed to parse:\n{}",
        t.failures.join("\n")
    );
    // At commit a2a9b716 the corpus holds 94 such values without macros (and 45 with); a much
    // smaller count means the walker broke.
    assert!(t.parsed >= 90, "only {} values found", t.parsed);
    assert!(
        t.polygons >= 10 && t.points >= 10,
        "unexpected mix: {} polygons, {} points",
        t.polygons,
        t.points
    );
}

#[test]
fn corpus_loiter_polygons_are_convex_and_contain_their_centre() {
    // Spot-check values that appear verbatim in the corpus.
    for s in [
        "radial:: x=110, y=-50, radius=20, pts=8, snap=1, label=HENRY_LOITER",
        "format=radial, label=obs, x=60, y=-115, radius=5, pts=12",
        "format=radial, x=20, y=-20, radius=23, pts=18, snap=1",
        "format=ellipse, x=60, y=-50, degs=90, minor=35, major=125, pts=16",
        "pts={-200,-200:30,-60:350,-60:130,-330:-100,-320}, label=loiter",
    ] {
        let v = parse_polygon(s).unwrap_or_else(|e| panic!("{s}: {e}"));
        assert!(v.polygon.is_convex(), "{s}");
        let c = v.polygon.centroid();
        assert!(v.polygon.contains(c.x, c.y), "{s}");
    }
    let e =
        parse_polygon("format=ellipse, x=60, y=-50, degs=90, minor=35, major=125, pts=16").unwrap();
    // Rotated 90 degrees: the 125 m axis runs north-south.
    assert!(e.polygon.contains(60.0, -50.0 + 62.0) && !e.polygon.contains(60.0 + 20.0, -50.0));
}
