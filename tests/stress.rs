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
//!    frictionless and with mu = 0.3.
//! 3. moving rigid targets: scenes/stress/moving_plane.toml (|Ft| = mu_d
//!    Fn) and incline.toml (onset at atan(mu_s)).
//! 4. load paths through the Solver API: the sliding block
//!    (scenes/verification/sliding_block.toml) and the quarter-wrap capstan,
//!    held, tiny, one large and reversed increments, and lift-off (block).
//! 5. the shipped frictional scenes refined: rubber sheet (80 x 8),
//!    Hertz with friction, Cattaneo-Mindlin (120 divisions).
//!
//! Run:
//!
//!     cargo test --release --test stress
//!     cargo test --release --test stress -- --nocapture   # rows and checks
//!
//! Many of these fail with the solver as it is (issue 11); the scenes'
//! headers say how their physics was checked apart from it.
mod common;

use common::stress::Variant;
use common::stress::families;

macro_rules! variants {
    ($case:ident) => {
        mod $case {
            use super::*;
            #[test]
            fn q4_1x() {
                families::$case(Variant::Q4_1X).assert();
            }
            #[test]
            fn q4_2x() {
                families::$case(Variant::Q4_2X).assert();
            }
            #[test]
            fn q8_1x() {
                families::$case(Variant::Q8_1X).assert();
            }
            #[test]
            fn q8_2x() {
                families::$case(Variant::Q8_2X).assert();
            }
        }
    };
}

variants!(capstan_half_wrap);
variants!(capstan_quarter_wrap);
variants!(capstan_half_wrap_frictionless);
variants!(capstan_quarter_wrap_frictionless);
variants!(shrink_fit_frictionless);
variants!(shrink_fit_with_friction);
variants!(moving_plane);
variants!(incline);
variants!(block_held);
variants!(block_tiny);
variants!(block_large);
variants!(block_reversal);
variants!(block_lift_off);
variants!(capstan_held);
variants!(capstan_tiny);
variants!(capstan_large);
variants!(capstan_reversal);
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
    /// docs/contact.md item 12.
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

/// The shipped 80-division mesh and the 8-node one are in the bench.
mod cattaneo_mindlin {
    use super::*;
    /// The 120-division cylinder on tests/data/cattaneo_block_120.msh.
    #[test]
    fn q4_120() {
        families::cattaneo_refined(Variant::Q4_1X).assert();
    }
}
