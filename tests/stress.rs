//! The contact stress suite (issue 11): one test per scene variant, each
//! with 4- and 8-node elements, on the base mesh and refined once (the
//! bench, benches/stress.rs, adds the meshes refined twice).
//!
//! Every test asserts (tests/common/stress.rs, `Outcome::findings`): each
//! increment converges with the scene's default solver settings, without
//! bisection; the median of the Newton iterations per increment is at most
//! 5 and the largest at most 15; after each converged increment the contact
//! conditions hold (`check_contact_conditions`: no node in contact in
//! tension, no sliding node whose friction works along its slip); the
//! closed form within the tolerance its scene's header justifies; and the
//! family's own demands (full slip where the closed form needs it, held
//! inputs that change nothing, ...).
//!
//! 1. capstan: scenes/stress/capstan_half_wrap.toml (theta = pi) and
//!    capstan_quarter_wrap.toml (pi/2), T2/T1 = exp(mu theta); both also
//!    frictionless (T2 = T1).
//! 2. shrink fit: scenes/stress/shrink_fit.toml, Lame's interface pressure,
//!    frictionless and with mu = 0.3; and with the rim's bore in 23 facets
//!    against the hub's 16 (no node faces a node; no closed form).
//! 3. moving rigid targets: scenes/stress/moving_plane.toml (|Ft| = mu_d
//!    Fn) and incline.toml (onset at atan(mu_s)).
//! 4. load paths through the Solver API: the sliding block
//!    (scenes/verification/sliding_block.toml) and the quarter-wrap capstan,
//!    held, tiny, one large and reversed increments, and lift-off (block).
//! 5. the shipped frictional scenes refined: rubber sheet (80 x 8),
//!    Hertz with friction, Cattaneo-Mindlin (120 divisions).
//! 6. Hertz pressed in one increment, frictionless and with mu = 10, and
//!    the Newton iterations against refinement.
//!
//! Run:
//!
//!     cargo test --release --test stress
//!     cargo test --release --test stress -- --nocapture   # rows and checks
//!
//! The variants that fail with the solver as it is are `#[ignore]`d with
//! what they show (issue 11 stays open for them):
//! `cargo test --release --test stress -- --ignored` runs them. The scenes'
//! headers say how their physics was checked apart from the solver.
mod common;

use common::stress::Variant;
use common::stress::families;

/// One test per variant; a variant that fails today is ignored with the
/// reason (run them with `-- --ignored`; the bench runs every case).
macro_rules! variant {
    ($case:ident, $name:ident, $v:expr) => {
        #[test]
        fn $name() {
            families::$case($v).assert();
        }
    };
    ($case:ident, $name:ident, $v:expr, $why:literal) => {
        #[test]
        #[ignore = $why]
        fn $name() {
            families::$case($v).assert();
        }
    };
}

mod capstan_half_wrap {
    use super::*;
    variant!(capstan_half_wrap, q4_1x, Variant::Q4_1X);
    variant!(capstan_half_wrap, q4_2x, Variant::Q4_2X);
    variant!(capstan_half_wrap, q8_1x, Variant::Q8_1X);
    variant!(capstan_half_wrap, q8_2x, Variant::Q8_2X);
}
mod capstan_quarter_wrap {
    use super::*;
    variant!(capstan_quarter_wrap, q4_1x, Variant::Q4_1X);
    variant!(capstan_quarter_wrap, q4_2x, Variant::Q4_2X);
    variant!(capstan_quarter_wrap, q8_1x, Variant::Q8_1X);
    variant!(capstan_quarter_wrap, q8_2x, Variant::Q8_2X);
}
mod capstan_half_wrap_frictionless {
    use super::*;
    variant!(capstan_half_wrap_frictionless, q4_1x, Variant::Q4_1X);
    variant!(capstan_half_wrap_frictionless, q4_2x, Variant::Q4_2X);
    variant!(capstan_half_wrap_frictionless, q8_1x, Variant::Q8_1X);
    variant!(capstan_half_wrap_frictionless, q8_2x, Variant::Q8_2X);
}
mod capstan_quarter_wrap_frictionless {
    use super::*;
    variant!(capstan_quarter_wrap_frictionless, q4_1x, Variant::Q4_1X);
    variant!(capstan_quarter_wrap_frictionless, q4_2x, Variant::Q4_2X);
    variant!(capstan_quarter_wrap_frictionless, q8_1x, Variant::Q8_1X);
    variant!(capstan_quarter_wrap_frictionless, q8_2x, Variant::Q8_2X);
}
mod shrink_fit_frictionless {
    use super::*;
    variant!(shrink_fit_frictionless, q4_1x, Variant::Q4_1X);
    variant!(shrink_fit_frictionless, q4_2x, Variant::Q4_2X);
    variant!(shrink_fit_frictionless, q8_1x, Variant::Q8_1X);
    variant!(shrink_fit_frictionless, q8_2x, Variant::Q8_2X);
}
mod shrink_fit_with_friction {
    use super::*;
    variant!(shrink_fit_with_friction, q4_1x, Variant::Q4_1X);
    variant!(shrink_fit_with_friction, q4_2x, Variant::Q4_2X);
    variant!(shrink_fit_with_friction, q8_1x, Variant::Q8_1X);
    variant!(shrink_fit_with_friction, q8_2x, Variant::Q8_2X);
}
mod shrink_fit_nonmatching_frictionless {
    use super::*;
    variant!(shrink_fit_nonmatching_frictionless, q4_1x, Variant::Q4_1X);
    variant!(shrink_fit_nonmatching_frictionless, q4_2x, Variant::Q4_2X);
    variant!(shrink_fit_nonmatching_frictionless, q8_1x, Variant::Q8_1X);
    variant!(shrink_fit_nonmatching_frictionless, q8_2x, Variant::Q8_2X);
}
mod shrink_fit_nonmatching_with_friction {
    use super::*;
    variant!(shrink_fit_nonmatching_with_friction, q4_1x, Variant::Q4_1X);
    variant!(shrink_fit_nonmatching_with_friction, q4_2x, Variant::Q4_2X);
    variant!(shrink_fit_nonmatching_with_friction, q8_1x, Variant::Q8_1X);
    variant!(shrink_fit_nonmatching_with_friction, q8_2x, Variant::Q8_2X);
}
mod moving_plane {
    use super::*;
    variant!(moving_plane, q4_1x, Variant::Q4_1X);
    variant!(moving_plane, q4_2x, Variant::Q4_2X);
    variant!(moving_plane, q8_1x, Variant::Q8_1X);
    variant!(moving_plane, q8_2x, Variant::Q8_2X);
}
mod incline {
    use super::*;
    variant!(incline, q4_1x, Variant::Q4_1X);
    variant!(incline, q4_2x, Variant::Q4_2X);
    variant!(incline, q8_1x, Variant::Q8_1X);
    variant!(incline, q8_2x, Variant::Q8_2X);
}
mod block_held {
    use super::*;
    variant!(block_held, q4_1x, Variant::Q4_1X);
    variant!(block_held, q4_2x, Variant::Q4_2X);
    variant!(block_held, q8_1x, Variant::Q8_1X);
    variant!(block_held, q8_2x, Variant::Q8_2X);
}
mod block_tiny {
    use super::*;
    variant!(block_tiny, q4_1x, Variant::Q4_1X);
    variant!(block_tiny, q4_2x, Variant::Q4_2X);
    variant!(block_tiny, q8_1x, Variant::Q8_1X);
    variant!(block_tiny, q8_2x, Variant::Q8_2X);
}
mod block_large {
    use super::*;
    variant!(block_large, q4_1x, Variant::Q4_1X);
    variant!(block_large, q4_2x, Variant::Q4_2X);
    variant!(block_large, q8_1x, Variant::Q8_1X);
    variant!(block_large, q8_2x, Variant::Q8_2X);
}
mod block_reversal {
    use super::*;
    variant!(block_reversal, q4_1x, Variant::Q4_1X);
    variant!(block_reversal, q4_2x, Variant::Q4_2X);
    variant!(block_reversal, q8_1x, Variant::Q8_1X);
    variant!(block_reversal, q8_2x, Variant::Q8_2X);
}
mod block_lift_off {
    use super::*;
    variant!(block_lift_off, q4_1x, Variant::Q4_1X);
    variant!(block_lift_off, q4_2x, Variant::Q4_2X);
    variant!(block_lift_off, q8_1x, Variant::Q8_1X);
    variant!(block_lift_off, q8_2x, Variant::Q8_2X);
}
mod capstan_held {
    use super::*;
    variant!(capstan_held, q4_1x, Variant::Q4_1X);
    variant!(capstan_held, q4_2x, Variant::Q4_2X);
    variant!(capstan_held, q8_1x, Variant::Q8_1X);
    variant!(capstan_held, q8_2x, Variant::Q8_2X);
}
mod capstan_tiny {
    use super::*;
    variant!(capstan_tiny, q4_1x, Variant::Q4_1X);
    variant!(capstan_tiny, q4_2x, Variant::Q4_2X);
    variant!(capstan_tiny, q8_1x, Variant::Q8_1X);
    variant!(capstan_tiny, q8_2x, Variant::Q8_2X);
}
mod capstan_large {
    use super::*;
    variant!(capstan_large, q4_1x, Variant::Q4_1X);
    variant!(capstan_large, q4_2x, Variant::Q4_2X);
    variant!(capstan_large, q8_1x, Variant::Q8_1X);
    variant!(capstan_large, q8_2x, Variant::Q8_2X);
}
mod capstan_reversal {
    use super::*;
    variant!(capstan_reversal, q4_1x, Variant::Q4_1X);
    variant!(capstan_reversal, q4_2x, Variant::Q4_2X);
    variant!(capstan_reversal, q8_1x, Variant::Q8_1X);
    variant!(capstan_reversal, q8_2x, Variant::Q8_2X);
}
// 5. Refined versions of the shipped frictional scenes. The tests run the
// meshes that fit the suite's time (about 60 s); benches/stress.rs adds the
// 8-node 80 x 8 rubber sheet, the 8-node Hertz mesh of 120 divisions (30000
// unknowns), Cattaneo-Mindlin on the shipped mesh and with 8-node elements,
// and the meshes refined twice.
mod rubber_sheet {
    use super::*;
    #[test]
    fn q4_40x4() {
        families::rubber_sheet(Variant::Q4_1X).assert();
    }
    /// docs/contact.md item 12 (the paper's decisions cannot take it).
    #[test]
    fn q4_80x8() {
        families::rubber_sheet(Variant::Q4_2X).assert();
    }
    #[test]
    fn q8_40x4() {
        families::rubber_sheet(Variant::Q8_1X).assert();
    }
}

mod hertz_friction {
    use super::*;
    #[test]
    fn q8_60() {
        families::hertz_friction(Variant::Q8_1X).assert();
    }
    #[test]
    fn q4_60() {
        families::hertz_friction(Variant::Q4_1X).assert();
    }
    #[test]
    fn q4_120() {
        families::hertz_friction(Variant::Q4_2X).assert();
    }
}

/// The contact zone closed from nothing in one increment; the bench runs the
/// meshes refined up to 6 times.
mod hertz_one_increment {
    use super::*;
    variant!(hertz_one_increment, q4_60, Variant::Q4_1X);
    variant!(hertz_one_increment, q4_120, Variant::Q4_2X);
    variant!(hertz_one_increment, q8_60, Variant::Q8_1X);
    variant!(hertz_one_increment, q8_120, Variant::Q8_2X);
}
mod hertz_high_friction {
    use super::*;
    variant!(hertz_high_friction, q4_60, Variant::Q4_1X);
    variant!(hertz_high_friction, q4_120, Variant::Q4_2X);
    variant!(hertz_high_friction, q8_60, Variant::Q8_1X);
    variant!(hertz_high_friction, q8_120, Variant::Q8_2X);
}

/// Issue 11: Newton iterations must not grow with mesh refinement. Hertz
/// pressed in one increment (frictionless, and with mu = 10), 60 and 120
/// divisions, 4- and 8-node: the refined mesh takes at most one iteration
/// more, and none more than 3. Why 3: iteration 0 is the predictor (no
/// contact yet); iteration 1 closes the penetrated nodes and its inner
/// solves settle the linearised problem's contact states, and for a small
/// strain body on a rigid flat that problem is the problem, so iteration 2
/// has the solution (its residual at round-off); a third is a check the
/// energy test needs when the round-off of the residual times the whole
/// correction is just above its tolerance (the 8-node 360-division mesh).
/// Before the inner solves settled opening and closing, the frictionless
/// counts were 6 and 8 (4-node), 9 and 10 (8-node), one more per doubling:
/// about log2 of the nodes closed in excess by the predictor.
#[test]
fn hertz_iterations_do_not_grow_with_refinement() {
    use common::stress::Element;
    type Family = fn(Variant) -> common::stress::Outcome;
    let cases: [(&str, Family); 2] = [
        ("frictionless", families::hertz_one_increment),
        ("mu = 10", families::hertz_high_friction),
    ];
    let mut failures = Vec::new();
    for (name, run) in cases {
        for element in [Element::Q4, Element::Q8] {
            let mut counts = Vec::new();
            for refine in [1, 2] {
                let out = run(Variant::new(element, refine));
                let st = out.stats();
                // A run that stopped, or bisected, has no count to compare.
                assert!(
                    out.run.failure.is_none() && st.bisections == 0 && st.increments == 1,
                    "hertz {name} {}: {}",
                    element.keyword(),
                    out.row()
                );
                counts.push(st.max);
            }
            println!("hertz {name} {}: iterations {counts:?}", element.keyword());
            if counts[1] > counts[0] + 1 || counts.iter().any(|&c| c > 3) {
                failures.push(format!("{name} {}: {counts:?}", element.keyword()));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "iterations at 60, 120 divisions: {failures:?}"
    );
}

/// The shipped 80-division mesh and the 8-node one are in the bench.
mod cattaneo_mindlin {
    use super::*;
    /// The 120-division cylinder on tests/data/cattaneo_block_120.msh.
    #[test]
    fn q4_120() {
        families::cattaneo_refined(Variant::Q4_1X).assert();
    }
}
