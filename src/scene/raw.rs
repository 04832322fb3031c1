//! The scene file's schema as serde reads it: every value keeps the byte span it came
//! from, so that validation can point at the exact place in the file.
//!
//! These types accept anything TOML can say in the right shape; `super::validate`
//! decides what is meaningful. Unknown keys are rejected here, by serde.

use serde::Deserialize;
use toml::Spanned;

/// A 2-D vector as a scene writes it: `[x, y]`, exactly two numbers.
///
/// serde's `[f64; 2]` would quietly ignore a third element, so `[1, 2, 3]` is read
/// through a sequence visitor that counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawVec2(pub [f64; 2]);

impl<'de> Deserialize<'de> for RawVec2 {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = RawVec2;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("two numbers [x, y]")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RawVec2, A::Error> {
                use serde::de::Error;
                let x: f64 = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(0, &self))?;
                let y: f64 = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(1, &self))?;
                let mut n = 2;
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    n += 1;
                }
                if n != 2 {
                    return Err(A::Error::invalid_length(n, &self));
                }
                Ok(RawVec2([x, y]))
            }
        }
        deserializer.deserialize_seq(Visitor)
    }
}

/// The whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    pub name: Option<Spanned<String>>,
    pub simulation: Option<Spanned<RawSimulation>>,
    pub render: Option<Spanned<RawRender>>,
    #[serde(default)]
    pub body: Vec<Spanned<RawBody>>,
    #[serde(default)]
    pub force: Vec<Spanned<RawForce>>,
    pub axes: Option<Spanned<super::layers::RawAxes>>,
    #[serde(default)]
    pub field: Vec<Spanned<super::layers::RawField>>,
    #[serde(default)]
    pub curve: Vec<Spanned<super::layers::RawCurve>>,
    #[serde(default)]
    pub swarm: Vec<Spanned<RawSwarm>>,
    pub contacts: Option<Spanned<RawContacts>>,
}

/// The `[contacts]` table: collisions on, and how they behave.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawContacts {
    pub restitution: Option<Spanned<f64>>,
    pub friction: Option<Spanned<f64>>,
    pub rest_speed: Option<Spanned<f64>>,
    pub slop: Option<Spanned<f64>>,
    pub iterations: Option<Spanned<i64>>,
    pub sleep: Option<Spanned<bool>>,
    pub sleep_speed: Option<Spanned<f64>>,
    pub sleep_time: Option<Spanned<f64>>,
    pub tolerance: Option<Spanned<f64>>,
    pub bodies: Option<Spanned<Vec<Spanned<String>>>>,
}

/// The `[simulation]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSimulation {
    pub integrator: Option<Spanned<String>>,
    pub dt: Option<Spanned<f64>>,
    pub duration: Option<Spanned<f64>>,
    pub rtol: Option<Spanned<f64>>,
    pub atol: Option<Spanned<f64>>,
    pub compare: Option<Spanned<Vec<Spanned<String>>>>,
}

/// The `[render]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRender {
    pub width: Option<Spanned<i64>>,
    pub height: Option<Spanned<i64>>,
    pub fps: Option<Spanned<f64>>,
    pub view: Option<Spanned<RawView>>,
    pub background: Option<Spanned<String>>,
    pub trails: Option<Spanned<bool>>,
    pub velocity_scale: Option<Spanned<f64>>,
    pub force_scale: Option<Spanned<f64>>,
    pub hud: Option<Spanned<bool>>,
    pub show_bodies: Option<Spanned<bool>>,
    pub show_springs: Option<Spanned<bool>>,
}

/// The world rectangle a frame shows.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawView {
    pub min: Spanned<RawVec2>,
    pub max: Spanned<RawVec2>,
}

/// One `[[body]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBody {
    pub name: Option<Spanned<String>>,
    pub mass: Option<Spanned<f64>>,
    pub position: Option<Spanned<RawVec2>>,
    pub velocity: Option<Spanned<RawVec2>>,
    pub shape: Option<Spanned<RawShape>>,
    pub points: Option<Spanned<Vec<Spanned<RawPointMass>>>>,
    pub color: Option<Spanned<String>>,
    pub show_velocity: Option<Spanned<bool>>,
    pub show_force: Option<Spanned<bool>>,
    pub angle: Option<Spanned<f64>>,
    pub angular_velocity: Option<Spanned<f64>>,
    pub inertia: Option<Spanned<f64>>,
    #[serde(rename = "static")]
    pub fixed: Option<Spanned<bool>>,
    pub restitution: Option<Spanned<f64>>,
    pub friction: Option<Spanned<f64>>,
}

/// One `[[swarm]]`: many bodies alike but for their seeded random initial state.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSwarm {
    pub name: Spanned<String>,
    pub count: Spanned<i64>,
    pub seed: Option<Spanned<i64>>,
    pub mass: Spanned<f64>,
    pub position: Spanned<RawRange>,
    pub velocity: Option<Spanned<RawRange>>,
    pub shape: Option<Spanned<RawShape>>,
    pub color: Option<Spanned<String>>,
    pub angle: Option<Spanned<RawScalarRange>>,
    pub angular_velocity: Option<Spanned<RawScalarRange>>,
    pub restitution: Option<Spanned<f64>>,
    pub friction: Option<Spanned<f64>>,
    pub layout: Option<Spanned<String>>,
}

/// An interval of numbers, from which a swarm draws values uniformly.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScalarRange {
    pub min: Spanned<f64>,
    pub max: Spanned<f64>,
}

/// A rectangle of 2-D vectors, from which a swarm draws values uniformly.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRange {
    pub min: Spanned<RawVec2>,
    pub max: Spanned<RawVec2>,
}

/// A body's shape: exactly one of the three keys.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawShape {
    pub circle: Option<Spanned<RawCircle>>,
    #[serde(rename = "box")]
    pub rect: Option<Spanned<RawBox>>,
    pub polygon: Option<Spanned<RawPolygon>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawCircle {
    pub radius: Spanned<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBox {
    pub width: Spanned<f64>,
    pub height: Spanned<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPolygon {
    pub points: Spanned<Vec<Spanned<RawVec2>>>,
}

/// One point mass of a body made of points (Equations 7-11).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPointMass {
    pub offset: Spanned<RawVec2>,
    pub mass: Spanned<f64>,
}

/// One `[[force]]`. Every kind's keys are optional here; validation checks that a kind
/// gets the keys it needs and no key that belongs to another kind.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawForce {
    pub kind: Spanned<String>,
    pub bodies: Option<Spanned<Vec<Spanned<String>>>>,
    pub g: Option<Spanned<RawVec2>>,
    pub k: Option<Spanned<f64>>,
    pub c: Option<Spanned<f64>>,
    pub f0: Option<Spanned<RawVec2>>,
    pub f1: Option<Spanned<RawVec2>>,
    pub a: Option<Spanned<String>>,
    pub b: Option<Spanned<toml::Value>>,
    pub stiffness: Option<Spanned<f64>>,
    pub rest_length: Option<Spanned<f64>>,
    pub damping: Option<Spanned<f64>>,
    #[serde(alias = "center")]
    pub centre: Option<Spanned<RawVec2>>,
    pub strength: Option<Spanned<f64>>,
    pub tau: Option<Spanned<f64>>,
    pub at: Option<Spanned<RawVec2>>,
    pub a_at: Option<Spanned<RawVec2>>,
    pub b_at: Option<Spanned<RawVec2>>,
}
