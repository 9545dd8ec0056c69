use super::*;

fn seg(a: [f64; 2], b: [f64; 2]) -> TargetSegment {
    let (xa, xb) = (Vector2::new(a[0], a[1]), Vector2::new(b[0], b[1]));
    TargetSegment::new(Segment::new(xa, xb).unwrap(), None)
}

/// A foot of the normal just beyond an end is referred to the end node:
/// beta exactly 1, the same normal overlap; beyond the tolerance, none.
#[test]
fn contact_point_beyond_an_end_is_the_end_node() {
    let s = seg([0.0, 0.0], [1.0, 0.0]);
    let x = Vector2::new(1.0 + 1e-8, 1e-8);
    let raw = s.seg.project(x);
    let cp = on_segment(&s.seg, x).unwrap();
    assert_eq!(cp.beta(), 1.0);
    assert!(raw.beta() > 1.0);
    assert_eq!(cp.normal_overlap(), raw.normal_overlap());
    assert_eq!(cp.point(), s.seg.xb());
    assert!(on_segment(&s.seg, Vector2::new(1.0 + 1e-3, 0.0)).is_none());
    let inside = on_segment(&s.seg, Vector2::new(0.25, 0.1)).unwrap();
    assert_eq!(inside.beta(), 0.25);
}

/// Reflex corners: the body lies to the left of A -> B, so a surface
/// that turns right (round a hole) has reflex corners, one that turns
/// left (round a disk) does not; a straight one has no corner.
#[test]
fn reflex_corners_turn_right() {
    // Turning right: (0,0) -> (1,0) -> (2,-0.1), body above.
    let right = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, -0.1])];
    assert_eq!(reflex(&right, 0, 1.0), Some((1, 0.0)));
    assert_eq!(reflex(&right, 1, 0.0), Some((0, 1.0)));
    assert_eq!(reflex(&right, 0, 0.0), None);
    let left = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, 0.1])];
    assert_eq!(reflex(&left, 0, 1.0), None);
    let straight = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, 0.0])];
    assert_eq!(reflex(&straight, 0, 1.0), None);
}

/// A free node that has penetrated next to a reflex corner, in the
/// wedge between the two segments' normals, is found at the corner.
#[test]
fn a_node_in_the_wedge_of_a_reflex_corner_is_found_at_the_corner() {
    // A valley (the target body below, walked from +x to -x): a node
    // 0.01 below its bottom projects beyond the end of both segments
    // (beta = 1.001 and -0.001).
    let valley = [seg([1.0, 0.1], [0.0, 0.0]), seg([0.0, 0.0], [-1.0, 0.1])];
    let x = Vector2::new(0.0, -0.01);
    for s in &valley {
        assert!(on_segment(&s.seg, x).is_none());
    }
    let (_, cp) =
        search(&TargetSet::new(valley.into()), x, 1.0, false).expect("penetrated node not found");
    assert_eq!(cp.point(), Vector2::zeros());
    assert!(cp.normal_overlap() > 0.0099 && cp.normal_overlap() <= 0.01);
}

#[test]
fn a_node_past_the_end_of_a_target_by_more_than_its_overlap_is_not_found() {
    let flat = TargetSet::new(vec![seg([1.0, 0.0], [0.0, 0.0])]);
    assert!(search(&flat, Vector2::new(-0.05, -0.01), 1.0, false).is_none());
    // Within its overlap of the end it is held at the end.
    let (_, cp) = search(&flat, Vector2::new(-0.005, -0.01), 1.0, false).unwrap();
    assert_eq!(cp.beta(), 1.0);
}

/// Numbers uniform in [0, 1) from `seed` (a linear congruential
/// generator: the tests' points and reaches, the same at every run).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A node's searches through the cache (`SearchCache`) find what fresh
/// searches find, while the node wanders in small and large steps about
/// the capstan's drum with reaches that grow and shrink, and when the
/// segments are another set (a new pose): its candidates are read again.
#[test]
fn cached_searches_find_what_fresh_searches_find() {
    let arc = |shift: f64| -> Vec<TargetSegment> {
        (0..2000)
            .map(|k| {
                let at = |k: usize| {
                    let a = -0.4 + 3.9 * k as f64 / 2000.0;
                    [100.0 * a.cos() + shift, 100.0 * a.sin()]
                };
                seg(at(k), at(k + 1))
            })
            .collect()
    };
    let sets = [
        Arc::new(TargetSet::new(arc(0.0))),
        Arc::new(TargetSet::new(arc(0.5))),
    ];
    let mut random = uniform(777);
    let mut cache = SearchCache::default();
    let mut x = Vector2::new(99.5, 3.0);
    let (mut hits, mut found) = (0, 0);
    for step in 0..4000 {
        let big = random() < 0.05;
        let d = if big { 3.0 } else { 0.02 };
        x += Vector2::new(d * (2.0 * random() - 1.0), d * (2.0 * random() - 1.0));
        let reach = [0.5, 1.0, 2.0, 5.0][(4.0 * random()) as usize % 4];
        let segments = &sets[usize::from(step % 500 >= 250)];
        let before = cache.0.get(&(0, 7)).map(|c| c.candidates.len());
        let cached = cache.search((0, 7), segments, x, reach);
        hits +=
            usize::from(before.is_some() && cache.0[&(0, 7)].candidates.len() == before.unwrap());
        found += usize::from(cached.is_some());
        assert_eq!(
            cached,
            search(segments, x, reach, false),
            "at {x:?}, reach {reach}"
        );
    }
    // Both paths taken, and contacts found as well as not.
    assert!(
        hits > 1000 && found > 100 && found < 3900,
        "{hits} hits, {found} found"
    );
}

/// The grid only narrows the candidates: `search`, `follow` and the
/// outputs' `nearest` give exactly what a scan of every segment gives,
/// on a fine arc (the capstan's drum), a wall (no extent across) and a
/// zigzag, at points near and far, for reaches small and large.
#[test]
fn the_grid_finds_what_a_full_scan_finds() {
    let arc: Vec<TargetSegment> = (0..2000)
        .map(|k| {
            let at = |k: usize| {
                let a = -0.4 + 3.9 * k as f64 / 2000.0;
                [100.0 * a.cos(), 100.0 * a.sin()]
            };
            seg(at(k), at(k + 1))
        })
        .collect();
    let wall: Vec<TargetSegment> = (0..64)
        .map(|k| seg([1.0, 64.0 - k as f64], [1.0, 63.0 - k as f64]))
        .collect();
    let zigzag: Vec<TargetSegment> = (0..100)
        .map(|k| {
            let y = |k: usize| if k.is_multiple_of(2) { 0.0 } else { 0.3 };
            seg([k as f64 * 0.1, y(k)], [(k + 1) as f64 * 0.1, y(k + 1)])
        })
        .collect();
    let mut random = uniform(12345);
    for (list, centre, size) in [
        (arc, [0.0, 0.0], 110.0),
        (wall, [1.0, 32.0], 40.0),
        (zigzag, [5.0, 0.15], 6.0),
    ] {
        let n = list.len();
        let gridded = TargetSet::new(list.clone());
        assert!(gridded.grid.is_some());
        let scanned = TargetSet { list, grid: None };
        for _ in 0..3000 {
            let near = random() < 0.5;
            let r = if near { 0.05 * size } else { size };
            let x = Vector2::new(
                centre[0] + r * (2.0 * random() - 1.0),
                centre[1] + r * (2.0 * random() - 1.0),
            );
            let reach = [1e-3, 0.1, 3.0, 1e3][(4.0 * random()) as usize % 4] * size / 100.0;
            let touching = random() < 0.5;
            let j = (random() * n as f64) as usize % n;
            assert_eq!(
                search(&gridded, x, reach, touching),
                search(&scanned, x, reach, touching),
                "search at {x:?}, reach {reach}"
            );
            assert_eq!(
                follow(&gridded, j, x, reach),
                follow(&scanned, j, x, reach),
                "follow from {j} at {x:?}, reach {reach}"
            );
            assert_eq!(
                super::super::outputs::nearest(&gridded, x),
                super::super::outputs::nearest(&scanned, x),
                "nearest to {x:?}"
            );
        }
    }
}
