//! Step 4 of Social Momentum, the comfort term (our addition, see the parent module's docs): the
//! agents whose comfort zone the robot could enter within the comfort horizon, and each sample's
//! mean intrusion into them.

use super::{Agent, COMFORT_SAMPLES, Scored, SocialMomentumParams};
use crate::control::Limits;
use crate::math::Vec2;

/// Step 4 of [`social_momentum`]: the agents whose comfort zone the robot could enter within the
/// comfort horizon, and what a sample's intrusion into them is.
pub(super) struct Comfort {
    /// Per agent: `pos - p_i`, `v_i`, `R_i`, the squared radius above which a squared distance
    /// surely gives a distance `>= R_i` (no intrusion, the term is exactly 0), and the first
    /// comfort instant (index) at which any sample could bring the robot into the zone (none
    /// can before: the robot covers at most `vmax t` by time `t`).
    pub(super) agents: Vec<ComfortAgent>,
    /// Per comfort instant `k`, the agents (indices into `agents`, ascending) whose zone some
    /// sample could reach at that instant: from `k >= first` on, and only while the agent's own
    /// position at `t_k` lies within `R_i + vmax t_k` of `pos` (the robot covers at most
    /// `vmax t_k`), with a margin far above rounding. The others' terms are exactly 0 there.
    pub(super) candidates: [Vec<usize>; COMFORT_SAMPLES],
    /// How many comfort instants to evaluate: one past the last instant with a candidate (0
    /// when no instant has one: every intrusion is 0).
    pub(super) instants: usize,
    pub(super) vel: Vec2,
    pub(super) goal_dir: Vec2,
    pub(super) accel: f64,
    pub(super) vmax: f64,
    pub(super) dt: f64,
    pub(super) horizon: f64,
}

impl Comfort {
    pub(super) fn new(
        pos: Vec2,
        vel: Vec2,
        goal_dir: Vec2,
        others: &[Agent],
        limits: &Limits,
        dt: f64,
        params: &SocialMomentumParams,
    ) -> Self {
        let vmax = limits.max_speed;
        let t_c = params.comfort_horizon;
        let h = t_c / COMFORT_SAMPLES as f64;
        let agents: Vec<ComfortAgent> = if params.comfort_weight > 0.0 && t_c > 0.0 {
            others
                .iter()
                .filter(|a| {
                    a.comfort > 0.0 && (pos - a.pos).norm() - a.comfort <= (vmax + a.vel.norm()) * t_c
                })
                .map(|a| {
                    let d0 = pos - a.pos;
                    // At instant t the robot is within vmax t of pos and the agent within
                    // |v_i| t of p_i: no intrusion while |d0| - (vmax + |v_i|) t clears R_i
                    // (by a margin far above rounding).
                    let (dist, closing) = (d0.norm(), vmax + a.vel.norm());
                    let first = (0..COMFORT_SAMPLES)
                        .find(|&k| dist - closing * ((k as f64 + 1.0) * h) < a.comfort + 1e-9)
                        .unwrap_or(COMFORT_SAMPLES);
                    ComfortAgent {
                        d0,
                        vel: a.vel,
                        r: a.comfort,
                        clear2: a.comfort * a.comfort * (1.0 + 1e-12),
                        first,
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let candidates = std::array::from_fn(|k| {
            let t = (k as f64 + 1.0) * h;
            // |q| <= vmax t (every step of the sample's way is clamped to vmax), so the robot's
            // offset `d0 + q - v_i t` is at least |d0 - v_i t| - vmax t from the agent.
            let reach = vmax * t * (1.0 + 1e-9) + 1e-6;
            (0..agents.len())
                .filter(|&i| {
                    let a = &agents[i];
                    k >= a.first && (a.d0 - a.vel * t).norm() - reach < a.r
                })
                .collect()
        });
        let instants = candidates.iter().rposition(|c: &Vec<usize>| !c.is_empty()).map_or(0, |k| k + 1);
        Comfort {
            agents,
            candidates,
            instants,
            vel,
            goal_dir,
            accel: limits.max_accel.min(1e3),
            vmax,
            dt,
            horizon: t_c,
        }
    }

    /// Mean intrusion (m) of the sample `v` into the comfort zones over the comfort horizon.
    #[cfg(test)]
    pub(super) fn intrusion(&self, v: Vec2) -> f64 {
        let mut one = [Scored { v, e: 0.0, sm: 0.0, c: 0.0 }];
        self.intrusions(&mut one);
        one[0].c
    }

    /// Sets `c` of every sample to its mean intrusion (m) into the comfort zones over the comfort
    /// horizon.
    ///
    /// The samples are processed side by side (one array per coordinate, a loop over the samples
    /// inside the loops over the instants and the candidates, without branches, which the compiler
    /// turns into SIMD code), each sample's sum in the same order and with the same operations as
    /// one sample at a time, so every result is the same bit for bit.
    pub(super) fn intrusions(&self, samples: &mut [Scored]) {
        let n = samples.len();
        if self.instants == 0 || n == 0 {
            for s in samples.iter_mut() {
                s.c = 0.0;
            }
            return;
        }
        // Per sample: its velocity, the acceleration it keeps up (turn * accel), where it has got
        // to (q) and the sum of its intrusions.
        let mut buf = vec![0.0; 7 * n];
        let (vx, rest) = buf.split_at_mut(n);
        let (vy, rest) = rest.split_at_mut(n);
        let (px, rest) = rest.split_at_mut(n);
        let (py, rest) = rest.split_at_mut(n);
        let (qx, rest) = rest.split_at_mut(n);
        let (qy, sum) = rest.split_at_mut(n);
        for (j, s) in samples.iter().enumerate() {
            // The sample's way over the horizon: it keeps accelerating the way it turned (at the
            // acceleration limit, up to the speed limit), so a step aside shows where it leads.
            let dv0 = s.v - self.vel;
            let turn = if dv0.norm() > 1e-9 { dv0 / dv0.norm() } else { Vec2::zeros() };
            let push = turn * self.accel;
            (vx[j], vy[j], px[j], py[j]) = (s.v.x, s.v.y, push.x, push.y);
        }
        let (gx, gy) = (self.goal_dir.x, self.goal_dir.y);
        let vmax = self.vmax;
        let h = self.horizon / COMFORT_SAMPLES as f64;
        // After the last instant with a candidate every term is 0: the sums are complete.
        for (k, candidates) in self.candidates.iter().enumerate().take(self.instants) {
            let t = (k as f64 + 1.0) * h;
            let ramp = (t - self.dt).max(0.0);
            for j in 0..n {
                // w = clamp_norm(v + push * ramp, vmax), as in `clamp_norm`.
                let (mut wx, mut wy) = (vx[j] + px[j] * ramp, vy[j] + py[j] * ramp);
                let norm = (wx * wx + wy * wy).sqrt();
                if norm > vmax && norm > 0.0 {
                    let scale = vmax / norm;
                    (wx, wy) = (wx * scale, wy * scale);
                }
                // Backing away from the partial goal counts as standing still: the robot may slow
                // down or sidestep for someone's comfort, but it does not retreat along its way.
                let back = (wx * gx + wy * gy).min(0.0);
                (wx, wy) = (wx - gx * back, wy - gy * back);
                qx[j] += wx * h;
                qy[j] += wy * h;
            }
            for &i in candidates {
                let a = &self.agents[i];
                let (shift_x, shift_y) = (a.vel.x * t, a.vel.y * t);
                for j in 0..n {
                    let (dx, dy) = ((a.d0.x + qx[j]) - shift_x, (a.d0.y + qy[j]) - shift_y);
                    let d2 = dx * dx + dy * dy;
                    // A term that is exactly 0 (no intrusion) adds +0: the sum is the same, bit
                    // for bit, as without it.
                    sum[j] += if d2 > a.clear2 { 0.0 } else { (a.r - d2.sqrt()).max(0.0) };
                }
            }
        }
        for (s, c) in samples.iter_mut().zip(sum.iter()) {
            s.c = c / COMFORT_SAMPLES as f64;
        }
    }
}

/// An agent of the comfort term (see [`Comfort`]).
pub(super) struct ComfortAgent {
    pub(super) d0: Vec2,
    pub(super) vel: Vec2,
    pub(super) r: f64,
    pub(super) clear2: f64,
    pub(super) first: usize,
}
