//! Tampered checkpoints: a saved part with one field changed or one byte flipped is refused, or
//! finishes to the very same answer; never to a different one.

use super::*;
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::{Integrator, PartialRun};
use serde_json::Value;

fn integrator() -> Integrator<impl mcint::Estimator> {
    Integrator::over_box(
        |x: &[f64]| (3.0 * x[0]).sin() + x[1],
        UniformBox::unit(2).unwrap(),
    )
    .sampler(Sobol::new(2, Scramble::Owen, 9).unwrap())
    .samples(1 << 15)
    .replicates(3)
    .label("tampering")
}

/// Every leaf of a JSON value, by its path.
fn leaves(value: &Value, path: Vec<String>, out: &mut Vec<Vec<String>>) {
    match value {
        Value::Object(map) => map.iter().for_each(|(k, v)| {
            let mut p = path.clone();
            p.push(k.clone());
            leaves(v, p, out);
        }),
        Value::Array(items) => items.iter().enumerate().for_each(|(i, v)| {
            let mut p = path.clone();
            p.push(i.to_string());
            leaves(v, p, out);
        }),
        _ => out.push(path),
    }
}

fn leaf_mut<'a>(value: &'a mut Value, path: &[String]) -> &'a mut Value {
    path.iter().fold(value, |v, key| match v {
        Value::Array(items) => &mut items[key.parse::<usize>().unwrap()],
        other => &mut other[key.as_str()],
    })
}

/// The answer of a tampered part, or `None` when it is refused.
fn finish(text: &[u8]) -> Option<mcint::Estimate> {
    let mut part: PartialRun = serde_json::from_slice(text).ok()?;
    let integrator = integrator();
    while !part.is_complete() {
        integrator.resume(&mut part, 2).ok()?;
    }
    integrator.finish(&part).ok()
}

proptest! {
    #![proptest_config(config(64, 0xc0ffee))]

    #[test]
    fn changed_fields_and_flipped_bytes_are_refused(
        leaf in any::<prop::sample::Index>(),
        change in 0..5usize,
        byte in any::<prop::sample::Index>(),
        bit in 0..8u32,
    ) {
        let integrator = integrator();
        let whole = integrator.run().unwrap();
        let mut part = integrator.run_part(0..2).unwrap();
        part.merge(integrator.run_part(4..5).unwrap()).unwrap();
        let mut json: Value = serde_json::to_value(&part).unwrap();
        let mut paths = Vec::new();
        leaves(&json, Vec::new(), &mut paths);
        let target = leaf_mut(&mut json, &paths[leaf.index(paths.len())]);
        *target = match (change, target.clone()) {
            (0, Value::Number(n)) => Value::from(n.as_f64().unwrap() * (1.0 + 1e-15) + 1e-300),
            (1, Value::Number(n)) => Value::from(n.as_u64().map_or(0, |v| v.wrapping_add(1))),
            (_, Value::String(s)) => Value::from(format!("{s}x")),
            (2, _) => Value::Null,
            (3, _) => Value::from(-1),
            _ => Value::from(0.5),
        };
        if let Some(e) = finish(serde_json::to_string(&json).unwrap().as_bytes()) {
            prop_assert_eq!(e, whole.clone());
        }
        let mut bytes = serde_json::to_vec(&part).unwrap();
        let at = byte.index(bytes.len());
        bytes[at] ^= 1 << bit;
        if let Some(e) = finish(&bytes) {
            prop_assert_eq!(e, whole);
        }
    }
}
