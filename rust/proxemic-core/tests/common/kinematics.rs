//! The robots simulated kinematically: each robot's command integrated exactly over one control
//! period, no MuJoCo, no contacts. One source for the integration tests (through `tests/common`)
//! and the examples (included by path from `examples/common`).

use proxemic_core::world::World;

/// Integrates each robot's command (robot frame, from `out`, the world's output rows) over one
/// control period of `dt` seconds from its `pose` in `out` into `state` (x, y, yaw, vx, vy, wz per
/// robot, the world-frame velocities): the robots simulated kinematically.
pub fn kinematics(world: &World, out: &[f64], state: &mut [f64], dt: f64) {
    let lay = world.layout();
    for i in 0..world.num_robots() {
        let row = &out[i * lay.stride..(i + 1) * lay.stride];
        let pose = &row[lay.pose.offset..lay.pose.offset + 3];
        let c = &row[lay.command.offset..lay.command.offset + 3];
        let (s, co) = pose[2].sin_cos();
        let (vx, vy) = (co * c[0] - s * c[1], s * c[0] + co * c[1]);
        state[6 * i..6 * i + 6].copy_from_slice(&[
            pose[0] + vx * dt,
            pose[1] + vy * dt,
            pose[2] + c[2] * dt,
            vx,
            vy,
            c[2],
        ]);
    }
}
