//! The `learned` planner's policy: a small multilayer perceptron trained with PPO
//! (`examples/train_ppo.py`, `docs/training.md`), read from a NumPy `.npz` array file and run
//! here with no ML framework.
//!
//! The file holds float32 arrays: `input_scale` (one divisor per input), optionally `subgoal`
//! (one value: the look-ahead in metres of the `subgoal` observation the policy was trained
//! with; absent or 0 for a policy without it), and for each layer
//! `k = 0, 1, ...` a weight matrix `w{k}` of shape (outputs, inputs) and a bias `b{k}` of shape
//! (outputs,). Every layer but the last is followed by `tanh` (stable-baselines3's PPO
//! `MlpPolicy`: two hidden layers of 64 with tanh, then the linear action mean); the output is
//! the deterministic action, clipped to [-1, 1] as `predict(deterministic=True)` clips it.
//!
//! The input is the env's observation flattened in sorted key order (`lidar`, `people`,
//! `people_mask`, `robot`, then `subgoal` for a policy trained with that sensor, each
//! row-major) and divided elementwise by `input_scale`: the scales
//! of the scenes the policy was trained on, kept with the weights (ours: one scale in every scene,
//! so a goal offset of 5 m means the same input everywhere; `proxemic.policy.FlatObservation`
//! divides by each env's own bounds instead, which differ with the map's diagonal).
//!
//! The shipped policy ([`shipped`]) is `python/proxemic/data/models/learned_policy.npz`, compiled
//! into the core.

use std::sync::OnceLock;

use crate::error::{CoreError, Result};

/// One dense layer: `y = W x + b`.
#[derive(Clone, Debug)]
struct Dense {
    /// Row-major (outputs x inputs).
    w: Vec<f32>,
    b: Vec<f32>,
    inputs: usize,
}

/// A policy network: the input scaling and the layers (tanh between them).
#[derive(Clone, Debug)]
pub struct LearnedPolicy {
    input_scale: Vec<f32>,
    subgoal: f64,
    layers: Vec<Dense>,
}

/// The shipped policy's file, compiled in.
const SHIPPED: &[u8] = include_bytes!("../../../../python/proxemic/data/models/learned_policy.npz");

/// The shipped policy (`python/proxemic/data/models/learned_policy.npz`), parsed once.
///
/// # Errors
/// [`CoreError::Input`] if the compiled-in file does not parse (a broken build).
pub fn shipped() -> Result<&'static LearnedPolicy> {
    static POLICY: OnceLock<std::result::Result<LearnedPolicy, String>> = OnceLock::new();
    POLICY
        .get_or_init(|| LearnedPolicy::from_npz(SHIPPED, "learned_policy.npz").map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| {
            CoreError::input("learned_policy.npz", "the policy array file the core was built with", e.clone())
        })
}

fn bad(file: &str, field: &str, expected: &str, found: impl Into<String>) -> CoreError {
    CoreError::input(format!("{file}: {field}"), expected, found)
}

impl LearnedPolicy {
    /// Parses a policy from the bytes of an `.npz` file (uncompressed, as `numpy.savez` writes
    /// it); `file` names it in errors.
    ///
    /// # Errors
    /// [`CoreError::Input`] naming the file and the array for a malformed archive, a missing
    /// or non-float32 array, or shapes that do not chain.
    pub fn from_npz(bytes: &[u8], file: &str) -> Result<Self> {
        let arrays = read_npz(bytes, file)?;
        let get = |name: &str| -> Result<&NpyArray> {
            arrays
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, a)| a)
                .ok_or_else(|| bad(file, name, "an array of that name in the archive", "none"))
        };
        let scale = get("input_scale")?;
        if scale.shape.len() != 1 || scale.data.iter().any(|s| !s.is_finite() || *s <= 0.0) {
            return Err(bad(
                file,
                "input_scale",
                "a 1-D array of positive finite values",
                format!("shape {:?}", scale.shape),
            ));
        }
        let subgoal = match get("subgoal") {
            Err(_) => 0.0,
            Ok(a) => match a.data.as_slice() {
                [v] if (0.0..=10.0).contains(v) && a.shape.len() <= 1 => f64::from(*v),
                _ => {
                    return Err(bad(
                        file,
                        "subgoal",
                        "one value in [0, 10] (metres)",
                        format!("shape {:?}, values {:?}", a.shape, a.data),
                    ));
                }
            },
        };
        let mut layers = Vec::new();
        let mut inputs = scale.data.len();
        for k in 0.. {
            let Ok(w) = get(&format!("w{k}")) else { break };
            let b = get(&format!("b{k}"))?;
            if w.shape.len() != 2 || w.shape[1] != inputs || b.shape != [w.shape[0]] {
                return Err(bad(
                    file,
                    &format!("w{k}/b{k}"),
                    &format!("shapes (n, {inputs}) and (n,)"),
                    format!("{:?} and {:?}", w.shape, b.shape),
                ));
            }
            if w.data.iter().chain(&b.data).any(|v| !v.is_finite()) {
                return Err(bad(file, &format!("w{k}/b{k}"), "finite values", "NaN or infinity"));
            }
            layers.push(Dense { w: w.data.clone(), b: b.data.clone(), inputs });
            inputs = w.shape[0];
        }
        if layers.is_empty() || inputs != 3 {
            return Err(bad(
                file,
                "w0, b0, ...",
                "layers ending in 3 outputs (vx, vy, wz)",
                format!("{inputs} outputs"),
            ));
        }
        Ok(Self { input_scale: scale.data.clone(), subgoal, layers })
    }

    /// Look-ahead (metres) of the `subgoal` observation the policy takes as its last two
    /// inputs; 0 for a policy without it.
    pub fn subgoal(&self) -> f64 {
        self.subgoal
    }

    /// Number of inputs (the flattened observation's length).
    pub fn inputs(&self) -> usize {
        self.input_scale.len()
    }

    /// The deterministic action (vx, vy, wz), normalised to [-1, 1], for one flattened
    /// observation `obs` (unscaled: the policy divides by its `input_scale`).
    ///
    /// # Errors
    /// [`CoreError::Input`] if `obs` has not [`LearnedPolicy::inputs`] values.
    pub fn act(&self, obs: &[f64]) -> Result<[f64; 3]> {
        if obs.len() != self.inputs() {
            return Err(CoreError::input(
                "learned policy observation",
                format!("{} values", self.inputs()),
                format!("{} values", obs.len()),
            ));
        }
        let mut x: Vec<f32> = obs.iter().zip(&self.input_scale).map(|(o, s)| *o as f32 / s).collect();
        let last = self.layers.len() - 1;
        for (k, layer) in self.layers.iter().enumerate() {
            let y: Vec<f32> = layer
                .w
                .chunks_exact(layer.inputs)
                .zip(&layer.b)
                .map(|(row, b)| {
                    let z = row.iter().zip(&x).map(|(w, v)| w * v).sum::<f32>() + b;
                    if k < last { z.tanh() } else { z }
                })
                .collect();
            x = y;
        }
        Ok([0, 1, 2].map(|j| f64::from(x[j]).clamp(-1.0, 1.0)))
    }
}

/// One float32 array of an `.npz` archive.
#[derive(Clone, Debug)]
struct NpyArray {
    shape: Vec<usize>,
    data: Vec<f32>,
}

fn le_u16(b: &[u8], at: usize) -> Option<usize> {
    Some(usize::from(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?)))
}

fn le_u32(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}

fn le_u64(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// The stored (uncompressed) `.npy` members of a zip archive, by name without `.npy`.
fn read_npz(bytes: &[u8], file: &str) -> Result<Vec<(String, NpyArray)>> {
    let truncated =
        || bad(file, "archive", "a zip archive as numpy.savez writes it", "a truncated or corrupt file");
    let mut at = 0;
    let mut out = Vec::new();
    while le_u32(bytes, at) == Some(0x0403_4b50) {
        let flags = le_u16(bytes, at + 6).ok_or_else(truncated)?;
        let method = le_u16(bytes, at + 8).ok_or_else(truncated)?;
        let mut size = u64::from(le_u32(bytes, at + 18).ok_or_else(truncated)?);
        let name_len = le_u16(bytes, at + 26).ok_or_else(truncated)?;
        let extra_len = le_u16(bytes, at + 28).ok_or_else(truncated)?;
        let name = bytes.get(at + 30..at + 30 + name_len).ok_or_else(truncated)?;
        let name = String::from_utf8_lossy(name).into_owned();
        if method != 0 || flags & 0x8 != 0 {
            return Err(bad(
                file,
                &name,
                "a stored member with its size in the header (numpy.savez, not savez_compressed)",
                format!("compression method {method}, flags {flags:#x}"),
            ));
        }
        let extra_start = at + 30 + name_len;
        if size == 0xFFFF_FFFF {
            // Zip64: the extra field 0x0001 holds the uncompressed, then the compressed size.
            let mut e = extra_start;
            while e + 4 <= extra_start + extra_len {
                let (id, len) =
                    (le_u16(bytes, e).ok_or_else(truncated)?, le_u16(bytes, e + 2).ok_or_else(truncated)?);
                if id == 1 {
                    size = le_u64(bytes, e + 4).ok_or_else(truncated)?;
                    break;
                }
                e += 4 + len;
            }
        }
        let start = extra_start + extra_len;
        let end = usize::try_from(size).ok().and_then(|s| start.checked_add(s)).ok_or_else(truncated)?;
        let member = bytes.get(start..end).ok_or_else(truncated)?;
        let key = name.strip_suffix(".npy").unwrap_or(&name).to_string();
        out.push((key.clone(), read_npy(member, file, &key)?));
        at = end;
    }
    if out.is_empty() {
        return Err(truncated());
    }
    Ok(out)
}

/// A little-endian float32, C-order `.npy` array.
fn read_npy(b: &[u8], file: &str, name: &str) -> Result<NpyArray> {
    let err = |what: &str| bad(file, name, "a little-endian float32 C-order .npy array", what.to_string());
    if b.get(..6) != Some(b"\x93NUMPY".as_slice()) {
        return Err(err("no .npy magic"));
    }
    let major = *b.get(6).ok_or_else(|| err("truncated header"))?;
    let (header_len, header_start) = if major == 1 {
        (le_u16(b, 8).ok_or_else(|| err("truncated header"))?, 10)
    } else {
        (le_u32(b, 8).ok_or_else(|| err("truncated header"))? as usize, 12)
    };
    let header = b.get(header_start..header_start + header_len).ok_or_else(|| err("truncated header"))?;
    let header = String::from_utf8_lossy(header);
    if !header.contains("'descr': '<f4'") {
        return Err(err(&format!("header {}", header.trim())));
    }
    if header.contains("'fortran_order': True") {
        return Err(err("Fortran order"));
    }
    let shape_text = header
        .split("'shape': (")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .ok_or_else(|| err("no shape in the header"))?;
    let shape: Vec<usize> = shape_text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| err(&format!("shape ({shape_text})")))?;
    let n: usize = shape.iter().product();
    let data = b.get(header_start + header_len..).ok_or_else(|| err("truncated data"))?;
    if data.len() != 4 * n {
        return Err(err(&format!("{} data bytes for shape {shape:?} ({} expected)", data.len(), 4 * n)));
    }
    let data = data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    Ok(NpyArray { shape, data })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_policy_parses_and_acts_in_range() {
        let p = shipped().expect("the shipped policy parses");
        let a = p.act(&vec![0.5; p.inputs()]).expect("an observation of the right size");
        assert!(a.iter().all(|v| (-1.0..=1.0).contains(v)));
        assert!(p.act(&[0.0; 3]).is_err());
    }

    #[test]
    fn broken_files_name_the_problem() {
        let e = LearnedPolicy::from_npz(b"not a zip", "x.npz").expect_err("not a zip").to_string();
        assert!(e.contains("x.npz") && e.contains("zip archive"), "{e}");
        let mut cut = SHIPPED.to_vec();
        cut.truncate(SHIPPED.len() / 2);
        assert!(LearnedPolicy::from_npz(&cut, "cut.npz").is_err());
    }
}
