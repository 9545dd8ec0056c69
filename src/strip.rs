//! A strip laid along a path round a drum: a free span in, the wrap, a free
//! span out. Its reference configuration is straight (a wire or belt is
//! straight when unloaded), along x from the supply end, and it is placed
//! on the path by bending alone: the mid-line keeps its length and each
//! cross-section stays normal to it. Pure geometry: the mesh generator,
//! the placement and the running strip's outputs read it.

use std::f64::consts::TAU;

/// The path of a strip of thickness `thickness` whose inner face lies on
/// the circle of `radius` about `center` from `start_angle` over `wrap`
/// (radians; positive counter-clockwise, the direction the material runs),
/// with straight free spans of length `spans` before and after; the strip
/// is laid along it stretched by `strain` (its mid-line's), so that a
/// scene can start it near the tension it will carry. Reference
/// coordinates: x from 0 (the supply end) to `length()` along the
/// mid-line, y across it from -t/2 to t/2, positive to the left of the
/// running direction (so that the placement keeps the elements'
/// orientation). Lengths along the path (`spans`, `wrap_length`,
/// `path_coordinate`) are placed lengths, `length` and `element`
/// reference ones.
#[derive(Clone, Debug, PartialEq)]
pub struct StripPath {
    pub center: [f64; 2],
    pub radius: f64,
    pub thickness: f64,
    pub start_angle: f64,
    pub wrap: f64,
    pub spans: [f64; 2],
    pub strain: f64,
    /// The reference length of an element along the strip (all alike).
    pub element: f64,
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

impl StripPath {
    /// +1 when the strip runs counter-clockwise round the drum, -1 when
    /// clockwise.
    fn sense(&self) -> f64 {
        self.wrap.signum()
    }

    /// The mid-line's radius on the drum.
    pub fn mid_radius(&self) -> f64 {
        self.radius + 0.5 * self.thickness
    }

    /// Length of the wrap's mid-line along the path.
    pub fn wrap_length(&self) -> f64 {
        self.mid_radius() * self.wrap.abs()
    }

    /// The strip's reference length.
    pub fn length(&self) -> f64 {
        (self.spans[0] + self.wrap_length() + self.spans[1]) / (1.0 + self.strain)
    }

    /// The reference y of the inner face (the one on the drum).
    pub fn inner_y(&self) -> f64 {
        0.5 * self.thickness * self.sense()
    }

    /// Angle about the center of the point at path coordinate s on the
    /// wrap.
    fn angle_at(&self, s: f64) -> f64 {
        self.start_angle + self.sense() * (s - self.spans[0]) / self.mid_radius()
    }

    /// Unit tangent (the running direction) where the mid-line is at
    /// angle `phi` on the drum.
    fn tangent_at_angle(&self, phi: f64) -> [f64; 2] {
        let s = self.sense();
        [-s * phi.sin(), s * phi.cos()]
    }

    /// The running direction along the free span in (at the supply end)
    /// and out (at the take-up end).
    pub fn tangent_in(&self) -> [f64; 2] {
        self.tangent_at_angle(self.start_angle)
    }

    pub fn tangent_out(&self) -> [f64; 2] {
        self.tangent_at_angle(self.start_angle + self.wrap)
    }

    /// Where the reference point `p` = (x, y) lies once placed: at path
    /// coordinate s = (1 + strain) x, on the wrap at the angle s reaches,
    /// in a span along that span's tangent from the tangent point; y
    /// toward the drum shortens the radius.
    pub fn place(&self, p: [f64; 2]) -> [f64; 2] {
        self.at_path([(1.0 + self.strain) * p[0], p[1]])
    }

    /// The point at path coordinate s and offset y across the strip.
    fn at_path(&self, p: [f64; 2]) -> [f64; 2] {
        let x_on = p[0].clamp(self.spans[0], self.spans[0] + self.wrap_length());
        let phi = self.angle_at(x_on);
        let r = self.mid_radius() - self.sense() * p[1];
        let t = self.tangent_at_angle(phi);
        let along = p[0] - x_on;
        [
            self.center[0] + r * phi.cos() + along * t[0],
            self.center[1] + r * phi.sin() + along * t[1],
        ]
    }

    /// The path coordinate s of the mid-line point nearest to `q`: the
    /// nearest of the
    /// span in (before its tangent point), the wrap (within its angles)
    /// and the span out (after its tangent point).
    pub fn path_coordinate(&self, q: [f64; 2]) -> f64 {
        let rm = self.mid_radius();
        let x1 = self.spans[0] + self.wrap_length();
        let rel = [q[0] - self.center[0], q[1] - self.center[1]];
        let mut best = (f64::INFINITY, 0.0);
        let mut offer = |distance: f64, x: f64| {
            if distance < best.0 {
                best = (distance, x);
            }
        };
        // The wrap: the angle swept from the start in the running sense,
        // taken within pi of the wrap's middle.
        let mid = 0.5 * self.wrap.abs();
        let swept = self.sense() * (rel[1].atan2(rel[0]) - self.start_angle);
        let swept = swept - TAU * ((swept - mid) / TAU).round();
        if (0.0..=self.wrap.abs()).contains(&swept) {
            offer(
                (dot(rel, rel).sqrt() - rm).abs(),
                self.spans[0] + rm * swept,
            );
        }
        for (x, t, before) in [
            (self.spans[0], self.tangent_in(), true),
            (x1, self.tangent_out(), false),
        ] {
            let a = self.at_path([x, 0.0]);
            let d = [q[0] - a[0], q[1] - a[1]];
            let along = dot(d, t);
            if (before && along <= 0.0) || (!before && along >= 0.0) {
                offer((d[0] * t[1] - d[1] * t[0]).abs(), x + along);
            }
        }
        if best.0.is_finite() {
            best.1
        } else {
            // Beside a tangent point, outside both spans and the wrap.
            let a = self.at_path([self.spans[0], 0.0]);
            let b = self.at_path([x1, 0.0]);
            let da = dot([q[0] - a[0], q[1] - a[1]], [q[0] - a[0], q[1] - a[1]]);
            let db = dot([q[0] - b[0], q[1] - b[1]], [q[0] - b[0], q[1] - b[1]]);
            if da <= db { self.spans[0] } else { x1 }
        }
    }

    /// The path length the mid-line runs when the drum turns by `turn`
    /// (radians, counter-clockwise positive): negative when it runs back.
    pub fn run_by_turn(&self, turn: f64) -> f64 {
        self.sense() * turn * self.mid_radius()
    }

    /// Where the point `q` lands when the strip runs `ds` along its path:
    /// at its path coordinate plus `ds` and its offset across the strip,
    /// its departure from the path kept. On the wrap that is the drum's
    /// rotation by `ds` over the mid-line's radius; in a span, a
    /// translation along it.
    pub fn carry(&self, q: [f64; 2], ds: f64) -> [f64; 2] {
        let s = self.path_coordinate(q);
        let on = s.clamp(self.spans[0], self.spans[0] + self.wrap_length());
        let t = self.tangent_at_angle(self.angle_at(on));
        let a = self.at_path([s, 0.0]);
        // The offset to the left of the running direction (`at_path`'s y).
        let y = (q[0] - a[0]) * -t[1] + (q[1] - a[1]) * t[0];
        let (from, to) = (self.at_path([s, y]), self.at_path([s + ds, y]));
        [q[0] + to[0] - from[0], q[1] + to[1] - from[1]]
    }

    /// The angle along the wrap from the take-up side's tangent point
    /// back toward the supply side (0 where the strip leaves the drum,
    /// |wrap| where it meets it) of the mid-line point nearest `q`; beyond
    /// the wrap the spans' lengths continue it at the mid-line's radius.
    pub fn angle_from_exit(&self, q: [f64; 2]) -> f64 {
        (self.spans[0] + self.wrap_length() - self.path_coordinate(q)) / self.mid_radius()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(wrap: f64) -> StripPath {
        StripPath {
            center: [1.0, -2.0],
            radius: 10.0,
            thickness: 0.5,
            start_angle: 0.3,
            wrap,
            spans: [4.0, 6.0],
            strain: 0.0,
            element: 1.0,
        }
    }

    #[test]
    fn carrying_turns_the_wrap_and_slides_the_spans() {
        for wrap in [2.5, -2.5] {
            let p = path(wrap);
            let turn = 0.01 * wrap.signum();
            let ds = p.run_by_turn(turn);
            assert!((ds - 0.01 * p.mid_radius()).abs() < 1e-12);
            // A point of the inner face on the wrap turns about the centre.
            let s = p.spans[0] + 0.5 * p.wrap_length();
            let q = p.at_path([s, p.inner_y()]);
            let c = p.carry(q, ds);
            let (r0, r1) = (
                [q[0] - p.center[0], q[1] - p.center[1]],
                [c[0] - p.center[0], c[1] - p.center[1]],
            );
            let angle = (r0[0] * r1[1] - r0[1] * r1[0]).atan2(dot(r0, r1));
            assert!((angle - turn).abs() < 1e-12, "{angle}");
            assert!((dot(r1, r1).sqrt() - p.radius).abs() < 1e-12);
            // A point beside the span in slides along it, its offset kept.
            let q = p.at_path([1.0, 0.2]);
            let c = p.carry([q[0] + 1e-3, q[1]], ds);
            let e = p.at_path([1.0 + ds, 0.2]);
            assert!((c[0] - e[0] - 1e-3).abs() < 1e-12 && (c[1] - e[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn placement_bends_without_stretching_the_mid_line() {
        for (wrap, strain) in [(2.5, 0.0), (-2.5, 0.0), (2.5, 0.02)] {
            let p = StripPath {
                strain,
                ..path(wrap)
            };
            let n = 400;
            let h = p.length() / n as f64;
            let arc = (1.0 + strain) * h;
            let mut last = p.place([0.0, 0.0]);
            for i in 1..=n {
                let x = p.place([i as f64 * h, 0.0]);
                let chord = ((x[0] - last[0]).powi(2) + (x[1] - last[1]).powi(2)).sqrt();
                // A chord of the wrap is shorter than its arc by a^3/(24 R^2).
                assert!((chord - arc).abs() < arc.powi(3) / (24.0 * 100.0) + 1e-12);
                last = x;
            }
            // The inner face lies on the drum along the wrap.
            for s in [4.0, 10.0, 4.0 + p.wrap_length()] {
                let q = p.place([s / (1.0 + strain), p.inner_y()]);
                let r = ((q[0] - 1.0).powi(2) + (q[1] + 2.0).powi(2)).sqrt();
                assert!((r - 10.0).abs() < 1e-12, "r = {r}");
            }
        }
    }

    #[test]
    fn placement_keeps_the_orientation() {
        for wrap in [2.5, -2.5] {
            let p = path(wrap);
            for x in [1.0, 8.0, p.length() - 1.0] {
                let a = p.place([x, 0.0]);
                let b = p.place([x + 1e-4, 0.0]);
                let c = p.place([x, 1e-4]);
                let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                assert!(det > 0.0, "x = {x}, wrap = {wrap}");
            }
        }
    }

    #[test]
    fn path_coordinate_inverts_the_placement() {
        for wrap in [2.5, -2.5, std::f64::consts::PI] {
            let p = path(wrap);
            for i in 0..=50 {
                let x = p.length() * i as f64 / 50.0;
                for y in [-0.25, 0.0, 0.25] {
                    let got = p.path_coordinate(p.place([x, y]));
                    assert!((got - x).abs() < 1e-9, "x = {x}, got {got}, wrap {wrap}");
                }
            }
            let exit = p.at_path([p.spans[0] + p.wrap_length(), 0.0]);
            assert!(p.angle_from_exit(exit).abs() < 1e-12);
            let entry = p.at_path([p.spans[0], 0.0]);
            assert!((p.angle_from_exit(entry) - wrap.abs()).abs() < 1e-12);
        }
    }
}
