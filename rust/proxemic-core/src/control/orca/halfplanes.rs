//! Agent half-planes and the incremental linear programs (LP1, LP2, LP3) that find the velocity
//! closest to the preferred one inside them (van den Berg et al. 2011, as in RVO2).

use super::{
    LP_EPS, Line, OrcaAgent, PASS_ON_RIGHT, PASS_TILT_FADE, TINY_SQ, cross, left_normal, normalize_or,
};
use crate::math::Vec2;

/// The half-plane of agent `a` against neighbour `b` (van den Berg et al. 2011, restated in
/// `docs/algorithms.md`). `ia`, `ib` are their indices, used only for the coincident-agents
/// fallback.
pub(super) fn agent_line(
    a: &OrcaAgent,
    b: &OrcaAgent,
    ia: usize,
    ib: usize,
    inv_tau: f64,
    dt: f64,
    tilt: f64,
) -> Line {
    let p = b.pos - a.pos;
    let v = a.vel - b.vel;
    let r = a.radius + b.radius;
    let r2 = r * r;
    let dist2 = p.norm_squared();
    let (dir, u);
    if dist2 > r2 {
        // Not colliding: cut-off disk of radius r/tau centred at p/tau, or one of the two legs.
        let w = v - p * inv_tau;
        let wl2 = w.norm_squared();
        let dot = w.dot(&p);
        if dot < 0.0 && dot * dot > r2 * wl2 {
            let wl = wl2.sqrt();
            let mut n = w / wl;
            let mut push = r * inv_tau - wl;
            if tilt > 0.0 {
                // Passing-side tilt near head-on: a tangent point rotated towards the passing side,
                // kept on the arc between the legs (n . (-p^) > R/|p|) so the line supports the VO.
                let dist = dist2.sqrt();
                let toward = -p / dist;
                let angle = n.dot(&toward).clamp(-1.0, 1.0).acos();
                let delta = tilt * (1.0 - angle / PASS_TILT_FADE);
                if delta > 0.0 {
                    let (s, c) = (if PASS_ON_RIGHT { delta } else { -delta }).sin_cos();
                    let m = Vec2::new(c * n.x - s * n.y, s * n.x + c * n.y);
                    if m.dot(&toward) > r / dist {
                        n = m;
                        push = r * inv_tau - w.dot(&n);
                    }
                }
            }
            dir = Vec2::new(n.y, -n.x);
            u = n * push;
        } else {
            let leg = (dist2 - r2).sqrt();
            dir = if cross(p, w) > 0.0 {
                // Left leg.
                Vec2::new(p.x * leg - p.y * r, p.x * r + p.y * leg) / dist2
            } else {
                // Right leg; also taken at det == 0 (exact head-on): PASS_ON_RIGHT.
                -Vec2::new(p.x * leg + p.y * r, -p.x * r + p.y * leg) / dist2
            };
            u = dir * v.dot(&dir) - v;
        }
    } else {
        // Overlapping: cut-off disk at time dt, pushing apart within one step.
        let inv_dt = 1.0 / dt;
        let w = v - p * inv_dt;
        let wl = w.norm();
        let n = if wl * wl > TINY_SQ && wl.is_finite() {
            w / wl
        } else {
            // Relative velocity exactly p/dt: move straight away from B; if coincident, along a fixed
            // axis whose sign is decided by (id, index) so the two agents move apart.
            let away = if (a.id, ia) < (b.id, ib) { Vec2::new(-1.0, 0.0) } else { Vec2::new(1.0, 0.0) };
            normalize_or(-p, away)
        };
        dir = Vec2::new(n.y, -n.x);
        u = n * (r * inv_dt - wl);
    }
    let alpha = if b.reciprocal { 0.5 } else { 1.0 };
    Line { point: a.vel + u * alpha, dir }
}

/// Optimises on line `i` subject to lines `0..i` and the speed disk (LP1). Returns false if infeasible.
pub(super) fn lp1(lines: &[Line], i: usize, speed: f64, opt: Vec2, dir_opt: bool, result: &mut Vec2) -> bool {
    let li = lines[i];
    let b = li.point.dot(&li.dir);
    let disc = b * b + speed * speed - li.point.norm_squared();
    if disc < 0.0 || disc.is_nan() {
        return false;
    }
    let sq = disc.sqrt();
    let mut t_left = -b - sq;
    let mut t_right = -b + sq;
    for lj in &lines[..i] {
        let den = cross(li.dir, lj.dir);
        let num = cross(lj.dir, li.point - lj.point);
        if den.abs() <= LP_EPS {
            if num < 0.0 {
                return false;
            }
            continue;
        }
        let t = num / den;
        if den >= 0.0 {
            t_right = t_right.min(t);
        } else {
            t_left = t_left.max(t);
        }
        if t_left > t_right {
            return false;
        }
    }
    *result = if dir_opt {
        if opt.dot(&li.dir) > 0.0 { li.point + li.dir * t_right } else { li.point + li.dir * t_left }
    } else {
        let t = li.dir.dot(&(opt - li.point));
        li.point + li.dir * t.clamp(t_left, t_right)
    };
    true
}

/// Closest point to `opt` (or furthest along direction `opt` if `dir_opt`) in the disk of radius
/// `speed` satisfying all lines (LP2). Returns the index of the first line that made it infeasible,
/// or `lines.len()` on success; on failure `result` holds the best point before that line.
pub(super) fn lp2(lines: &[Line], speed: f64, opt: Vec2, dir_opt: bool, result: &mut Vec2) -> usize {
    *result = if dir_opt {
        opt * speed
    } else if opt.norm_squared() > speed * speed {
        normalize_or(opt, Vec2::zeros()) * speed
    } else {
        opt
    };
    for (i, l) in lines.iter().enumerate() {
        if cross(l.dir, l.point - *result) > 0.0 {
            let before = *result;
            if !lp1(lines, i, speed, opt, dir_opt, result) {
                *result = before;
                return i;
            }
        }
    }
    lines.len()
}

/// Minimises the largest violation of the agent lines `n_obst..` from `begin` on, keeping the
/// obstacle lines `..n_obst` hard (LP3).
pub(super) fn lp3(
    lines: &[Line],
    n_obst: usize,
    begin: usize,
    speed: f64,
    result: &mut Vec2,
    proj: &mut Vec<Line>,
) {
    let mut dist = 0.0;
    for i in begin..lines.len() {
        let li = lines[i];
        if cross(li.dir, li.point - *result) > dist {
            proj.clear();
            proj.extend_from_slice(&lines[..n_obst]);
            for lj in &lines[n_obst..i] {
                let den = cross(li.dir, lj.dir);
                let point = if den.abs() <= LP_EPS {
                    if li.dir.dot(&lj.dir) > 0.0 {
                        continue;
                    }
                    (li.point + lj.point) * 0.5
                } else {
                    li.point + li.dir * (cross(lj.dir, li.point - lj.point) / den)
                };
                proj.push(Line { point, dir: normalize_or(lj.dir - li.dir, left_normal(li.dir)) });
            }
            let before = *result;
            if lp2(proj, speed, left_normal(li.dir), true, result) < proj.len() {
                // Only through rounding: keep the previous point.
                *result = before;
            }
            dist = cross(li.dir, li.point - *result);
        }
    }
}
