//! parry, measured beside dvh (placeholder until its driver is written).

use crate::method::{Counters, Method};
use crate::scene::Scene;

#[derive(Default)]
pub struct Parry {}

impl Method for Parry {
    fn name(&self) -> String {
        "parry".into()
    }
    fn build(&mut self, _scene: &Scene, _world: &[Vec<f64>]) {}
    fn update(&mut self, _object: usize, _world: &[f64]) -> Option<u64> {
        None
    }
    fn collide(&mut self, _a: usize, _b: usize, out: &mut Vec<u64>) -> Option<Counters> {
        out.clear();
        None
    }
}
