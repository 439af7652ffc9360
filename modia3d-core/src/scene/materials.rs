//! Scene stage: solid materials and contact-pair materials, their built-in palettes (data from
//! Modia3D.jl's palettes, see `reference/materials.md`) and user palettes loaded from JSON.
//! Plain data; validation checks the ranges.

use serde::de::{Deserializer, Error as _, MapAccess, Visitor};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;

/// Mechanical data of a solid material. In a JSON palette every field is required and an
/// unknown field (e.g. a misspelt `poisson_ration`) is an error.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidMaterial {
    /// Density [kg/m³].
    pub density: f64,
    /// Young's modulus [N/m²].
    pub young_modulus: f64,
    /// Poisson's ratio [-], 0 < ν < 1.
    pub poisson_ratio: f64,
}

/// The built-in solid materials: (name, material).
pub const SOLID_MATERIALS: &[(&str, SolidMaterial)] = &[
    ("Steel", mat(8000.0, 2.0e11, 0.30)),
    ("Aluminium", mat(2700.0, 6.9e10, 0.32)),
    ("DryWood", mat(700.0, 1.1e10, 0.40)),
    ("BilliardBall", mat(1768.0, 5.4e9, 0.34)),
    ("BilliardTable", mat(700.0, 1.1e10, 0.40)),
    ("BilliardCushion", mat(700.0, 1.1e10, 0.40)),
    ("BilliardCue", mat(700.0, 1.1e10, 0.40)),
];

const fn mat(density: f64, young_modulus: f64, poisson_ratio: f64) -> SolidMaterial {
    SolidMaterial {
        density,
        young_modulus,
        poisson_ratio,
    }
}

/// Looks up a built-in solid material by name.
pub fn builtin_solid_material(name: &str) -> Option<SolidMaterial> {
    SOLID_MATERIALS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, m)| *m)
}

/// Response data of a pair of contact materials (the order of the pair does not matter).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactPairMaterial {
    /// Coefficient of restitution [-], 0 ≤ cor ≤ 1.
    pub cor: f64,
    /// Kinetic (sliding) friction coefficient μ_k [-], ≥ 0.
    pub mu_k: f64,
    /// Rotational (rolling) resistance coefficient μ_r [-], ≥ 0.
    pub mu_r: f64,
    /// Velocity [m/s] below which friction and `cor` are regularised; `None` = the scene's
    /// `v_min` (default 0.01 m/s).
    #[serde(default)]
    pub v_min: Option<f64>,
    /// Angular velocity [rad/s] below which the rolling torque is regularised; `None` = the
    /// scene's `w_min` (default 0.01 rad/s).
    #[serde(default)]
    pub w_min: Option<f64>,
}

impl ContactPairMaterial {
    /// A pair material with the scene's default `v_min` and `w_min`.
    pub const fn new(cor: f64, mu_k: f64, mu_r: f64) -> Self {
        ContactPairMaterial {
            cor,
            mu_k,
            mu_r,
            v_min: None,
            w_min: None,
        }
    }
    /// Sets the per-pair regularisation velocity `v_min` [m/s].
    pub fn v_min(mut self, v: f64) -> Self {
        self.v_min = Some(v);
        self
    }
    /// Sets the per-pair regularisation angular velocity `w_min` [rad/s].
    pub fn w_min(mut self, w: f64) -> Self {
        self.w_min = Some(w);
        self
    }
}

/// The built-in contact-pair materials: (name 1, name 2, material).
pub const CONTACT_PAIR_MATERIALS: &[(&str, &str, ContactPairMaterial)] = &[
    ("Steel", "Steel", ContactPairMaterial::new(0.7, 0.5, 0.001)),
    (
        "DryWood",
        "DryWood",
        ContactPairMaterial::new(0.6, 0.3, 0.001),
    ),
    (
        "BilliardBall",
        "BilliardBall",
        ContactPairMaterial::new(1.0, 0.0, 0.0),
    ),
    (
        "BilliardBall",
        "BilliardTable",
        ContactPairMaterial::new(0.0, 0.8, 0.01),
    ),
    (
        "BilliardBall",
        "BilliardCushion",
        ContactPairMaterial::new(0.98, 0.0, 0.0),
    ),
    (
        "BilliardBall",
        "BilliardCue",
        ContactPairMaterial::new(0.98, 0.0, 0.0),
    ),
    (
        "BilliardTable",
        "BilliardCue",
        ContactPairMaterial::new(0.0, 0.8, 0.01),
    ),
    (
        "BilliardCue",
        "BilliardCue",
        ContactPairMaterial::new(0.98, 0.0, 0.0),
    ),
];

/// Looks up a built-in contact-pair material (either order).
pub fn builtin_contact_pair(a: &str, b: &str) -> Option<ContactPairMaterial> {
    CONTACT_PAIR_MATERIALS
        .iter()
        .find(|(x, y, _)| (*x == a && *y == b) || (*x == b && *y == a))
        .map(|(_, _, m)| *m)
}

/// One entry of the `contact_pairs` list of a material file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactPairEntry {
    /// The two contact material names (any order).
    pub materials: [String; 2],
    /// The pair's data.
    #[serde(flatten)]
    pub material: ContactPairMaterial,
}

/// A user palette as read from a JSON file:
///
/// ```json
/// { "solid": { "Rubber": { "density": 1100, "young_modulus": 5e7, "poisson_ratio": 0.45 } },
///   "contact_pairs": [ { "materials": ["Rubber", "Steel"], "cor": 0.5, "mu_k": 0.8,
///                        "mu_r": 0.01, "v_min": 0.01 } ] }
/// ```
///
/// Both sections are optional. Units as in [`SolidMaterial`] and [`ContactPairMaterial`].
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialPalette {
    /// Solid materials by name (a name given twice is an error, not "the last one wins").
    #[serde(default, deserialize_with = "unique_solids")]
    pub solid: BTreeMap<String, SolidMaterial>,
    /// Contact-pair materials.
    #[serde(default)]
    pub contact_pairs: Vec<ContactPairEntry>,
}

/// The `solid` section: names to materials, each name once; an error inside a material names
/// it (serde's own map would keep the last of two equal keys without a word).
fn unique_solids<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<BTreeMap<String, SolidMaterial>, D::Error> {
    struct Solids;
    impl<'de> Visitor<'de> for Solids {
        type Value = BTreeMap<String, SolidMaterial>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("an object of solid materials by name")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(name) = map.next_key::<String>()? {
                if out.contains_key(&name) {
                    return Err(A::Error::custom(format!(
                        "solid material `{name}` is defined twice in section `solid`: keep one definition"
                    )));
                }
                let m = map.next_value::<SolidMaterial>().map_err(|e| {
                    A::Error::custom(format!(
                        "solid material `{name}`: {}",
                        without_position(&e.to_string())
                    ))
                })?;
                out.insert(name, m);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Solids)
}

/// `message` without serde_json's trailing ` at line L column C` (the position is reported
/// in fields of its own).
fn without_position(message: &str) -> &str {
    let mut m = message;
    while let Some((head, tail)) = m.rsplit_once(" at line ") {
        let is_position = tail.split_once(" column ").is_some_and(|(l, c)| {
            [l, c]
                .iter()
                .all(|s| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()))
        });
        if !is_position {
            break;
        }
        m = head;
    }
    m
}

/// A material file that cannot be read or parsed.
#[derive(thiserror::Error, Debug)]
pub enum MaterialFileError {
    /// The file cannot be read.
    #[error("cannot read material file `{path}`: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The JSON is malformed or has unknown or missing fields.
    #[error("material file `{path}`, line {line}, column {column}: {message} (expected sections `solid` and `contact_pairs`, see `MaterialPalette`)")]
    Parse {
        /// The path (or `<string>`).
        path: String,
        /// Line (1-based).
        line: usize,
        /// Column (1-based).
        column: usize,
        /// What is wrong.
        message: String,
    },
}

impl MaterialPalette {
    /// Parses a palette from JSON text; `origin` names it in errors.
    pub fn from_json_str(text: &str, origin: &str) -> Result<Self, MaterialFileError> {
        serde_json::from_str(text).map_err(|e| MaterialFileError::Parse {
            path: origin.to_string(),
            line: e.line(),
            column: e.column(),
            message: without_position(&e.to_string()).to_string(),
        })
    }
    /// Reads a palette from a JSON file.
    pub fn from_json_file(path: impl AsRef<std::path::Path>) -> Result<Self, MaterialFileError> {
        let p = path.as_ref();
        let text = std::fs::read_to_string(p).map_err(|source| MaterialFileError::Io {
            path: p.display().to_string(),
            source,
        })?;
        Self::from_json_str(&text, &p.display().to_string())
    }
}
