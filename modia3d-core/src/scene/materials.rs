//! Scene stage: solid materials and contact-pair materials, the built-in palette (the file
//! `palette.json` beside this one, compiled in: engineering materials with E, ν, density and
//! contact pairs with cor, μ_k, μ_r, every row citing its source) and user palettes loaded
//! from JSON. Plain data; validation checks the ranges.

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

/// A built-in solid material: its name, data and the keys of its sources.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltinSolid {
    /// The name, e.g. `"Steel"`.
    pub name: String,
    /// Density [kg/m³], Young's modulus [N/m²], Poisson's ratio [-].
    pub material: SolidMaterial,
    /// Keys into [`BuiltinPalette::sources`].
    pub source: Vec<String>,
    /// Display colour (sRGB) the HTML player draws solids of this material in.
    pub color: [u8; 3],
}

/// A built-in contact-pair material: its two contact material names, data and sources.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltinPair {
    /// The two contact material names (any order).
    pub materials: [String; 2],
    /// cor, μ_k, μ_r.
    pub material: ContactPairMaterial,
    /// Keys into [`BuiltinPalette::sources`].
    pub source: Vec<String>,
}

/// The built-in palette, read once from `modia3d-core/src/scene/palette.json` (compiled in):
/// the common engineering materials — `Steel`, `StainlessSteel`, `Aluminium`, `Brass`,
/// `Copper`, `Titanium`, `CastIron`, `Glass`, `Concrete`, `Granite`, `NaturalRubber`,
/// `Neoprene`, `PTFE`, `Nylon` (PA), `ABS`, `PVC`, `POM`, `DryWood`, `WetWood`, `Ice`,
/// `Ceramic` (alumina) — and Modia3D's billiard set (`BilliardBall`, `BilliardTable`,
/// `BilliardCushion`, `BilliardCue`), with contact pairs for every self-pair and the common
/// combinations (most against `Steel`); each row cites its source (handbooks and papers, listed
/// in [`sources`](Self::sources)). A pair that is missing is an error when a scene needs it,
/// unless `SceneOptions::average_missing_pairs` is set: then the mean of the two self-pairs is
/// used (Modia3D's rule), with a warning.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltinPalette {
    /// Citations by key.
    pub sources: BTreeMap<String, String>,
    /// The solid materials, sorted by name.
    pub solids: Vec<BuiltinSolid>,
    /// The contact-pair materials, in the file's order.
    pub pairs: Vec<BuiltinPair>,
}

/// The palette file's text.
pub const PALETTE_JSON: &str = include_str!("palette.json");

/// The palette file's layout (each row with a `source` list).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PaletteFile {
    #[allow(dead_code)]
    about: String,
    sources: BTreeMap<String, String>,
    solid: serde_json::Map<String, serde_json::Value>,
    contact_pairs: Vec<PairRow>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SolidRow {
    density: f64,
    young_modulus: f64,
    poisson_ratio: f64,
    color: String,
    source: Vec<String>,
}

/// `#rrggbb` → RGB.
fn parse_color(text: &str) -> Option<[u8; 3]> {
    let hex = text.strip_prefix('#').filter(|h| h.len() == 6)?;
    let byte = |i: usize| u8::from_str_radix(hex.get(i..i + 2)?, 16).ok();
    Some([byte(0)?, byte(2)?, byte(4)?])
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PairRow {
    materials: [String; 2],
    cor: f64,
    mu_k: f64,
    mu_r: f64,
    source: Vec<String>,
}

impl BuiltinPalette {
    /// Parses a palette in the layout of `palette.json` (`about`, `sources`, `solid` with
    /// `source` lists, `contact_pairs` with `source` lists); `Err` says what is wrong.
    pub fn parse(text: &str) -> Result<Self, String> {
        let file: PaletteFile = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let mut solids = vec![];
        for (name, value) in file.solid {
            let row: SolidRow = serde_json::from_value(value)
                .map_err(|e| format!("solid material `{name}`: {e}"))?;
            let color = parse_color(&row.color).ok_or_else(|| {
                format!(
                    "solid material `{name}`: colour `{}` is not #rrggbb",
                    row.color
                )
            })?;
            solids.push(BuiltinSolid {
                name,
                material: mat(row.density, row.young_modulus, row.poisson_ratio),
                source: row.source,
                color,
            });
        }
        let pairs = file
            .contact_pairs
            .into_iter()
            .map(|r| BuiltinPair {
                materials: r.materials,
                material: ContactPairMaterial::new(r.cor, r.mu_k, r.mu_r),
                source: r.source,
            })
            .collect();
        Ok(BuiltinPalette {
            sources: file.sources,
            solids,
            pairs,
        })
    }
}

/// The built-in palette (parsed on first use; the file is checked by the crate's tests, so
/// parsing cannot fail in a released build — should it, the palette is empty and every
/// built-in name is reported unknown rather than panicking).
pub fn builtin_palette() -> &'static BuiltinPalette {
    static PALETTE: std::sync::OnceLock<BuiltinPalette> = std::sync::OnceLock::new();
    PALETTE.get_or_init(|| {
        BuiltinPalette::parse(PALETTE_JSON).unwrap_or(BuiltinPalette {
            sources: BTreeMap::new(),
            solids: vec![],
            pairs: vec![],
        })
    })
}

/// Names of the built-in solid materials, in the palette's order.
pub fn builtin_solid_names<'a>() -> impl Iterator<Item = &'a str> {
    builtin_palette()
        .solids
        .iter()
        .map(|s| -> &'a str { s.name.as_str() })
}

const fn mat(density: f64, young_modulus: f64, poisson_ratio: f64) -> SolidMaterial {
    SolidMaterial {
        density,
        young_modulus,
        poisson_ratio,
    }
}

/// The display colour (sRGB) of a built-in solid material.
pub fn builtin_material_color(name: &str) -> Option<[u8; 3]> {
    builtin_palette()
        .solids
        .iter()
        .find(|s| s.name == name)
        .map(|s| s.color)
}

/// Looks up a built-in solid material by name.
pub fn builtin_solid_material(name: &str) -> Option<SolidMaterial> {
    builtin_palette()
        .solids
        .iter()
        .find(|s| s.name == name)
        .map(|s| s.material)
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

/// Looks up a built-in contact-pair material (either order).
pub fn builtin_contact_pair(a: &str, b: &str) -> Option<ContactPairMaterial> {
    builtin_palette()
        .pairs
        .iter()
        .find(|p| {
            let [x, y] = &p.materials;
            (x == a && y == b) || (x == b && y == a)
        })
        .map(|p| p.material)
}

/// The mean of two contact-pair materials (cor, μ_k, μ_r; `v_min`/`w_min` the mean of those
/// given, else the one given): Modia3D's rule for a pair `a|b` that is not defined, from the
/// self-pairs `a|a` and `b|b` (used only with `SceneOptions::average_missing_pairs`).
pub fn average_pair(p: &ContactPairMaterial, q: &ContactPairMaterial) -> ContactPairMaterial {
    let mean = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some(0.5 * (x + y)),
        (x, y) => x.or(y),
    };
    ContactPairMaterial {
        cor: 0.5 * (p.cor + q.cor),
        mu_k: 0.5 * (p.mu_k + q.mu_k),
        mu_r: 0.5 * (p.mu_r + q.mu_r),
        v_min: mean(p.v_min, q.v_min),
        w_min: mean(p.w_min, q.w_min),
    }
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
