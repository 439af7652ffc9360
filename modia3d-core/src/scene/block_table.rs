//! The table of block kinds ([`BLOCK_KINDS`]): per block of [`crate::scene::blocks`] its
//! parameter keys (the struct's fields, Modelica's names), its input ports and its signals
//! (outputs with their feedthrough flags, continuous and discrete states). `model!` checks
//! and expands a component entry with it, as it does joints with `JOINT_KINDS`; the builder API
//! does not read it (a block states its ports itself, [`crate::scene::Component`]).
//! `modia3d-core/tests/block_table.rs` fails when a block has no row or a row disagrees with
//! the block's own `inputs()`, `outputs()`, `states()` and `discrete_states()`.

use super::blocks::{Drive, Gain, Limiter, PtpPath, Ramp, Sampled, PI};
use super::components::Component;
use std::sync::Arc;

/// What a block parameter takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockValue {
    /// An `f64`.
    Number,
    /// A list of numbers (`Vec<f64>`: one per axis).
    Numbers,
    /// Rows of numbers (`Vec<Vec<f64>>`: a `PtpPath`'s points).
    Rows,
    /// `(time, value)` rows (`Vec<(f64, f64)>`: a `Table`).
    Pairs,
    /// The name of a joint of the scene (a `Drive`'s `joint`).
    Joint,
    /// A scalar coordinate of that joint, as a string (`"phi2"`); needed on a joint with
    /// several.
    Coordinate,
    /// One of the variants of an enum field (a `Drive`'s `gear`: `Rigid` or
    /// `Elastic { c, d }`), which may change the block's ports and states (see
    /// [`BlockKindSpec::example`]); the first is the default.
    Variant(&'static [BlockVariant]),
    /// A block of another kind without its inputs, written as its constructor (a `Sampled`
    /// block's `inner = PI(k = …, T = …)`), whose kind changes the block's ports (see
    /// [`BlockKindSpec::example`]: chosen by the kind's name).
    Block,
}

/// A variant of an enum-valued block parameter ([`BlockValue::Variant`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockVariant {
    /// The variant's name (`"Elastic"`), the constructor in `model!` (`Elastic(c = …, d = …)`).
    pub name: &'static str,
    /// Its fields, all required (`["c", "d"]`).
    pub fields: &'static [&'static str],
}

/// The variants chosen for a block's enum-valued parameters, by key (`"gear"` →
/// `Some("Elastic")`); `None`: the default (the first).
pub type BlockVariants<'a> = dyn Fn(&str) -> Option<&'static str> + 'a;

/// A parameter of a block kind: a field of its struct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockParam {
    /// The key, the struct's field (`"k"`, `"startTime"`).
    pub key: &'static str,
    /// What it takes.
    pub value: BlockValue,
    /// Its default, as text for messages and docs (`"1"`, `"−uMax"`); `None`: required.
    pub default: Option<&'static str>,
}

/// An output of a block kind (a signal `<block>.<name>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockOutput {
    /// Its name (`"y"`, `"motor_phi"`).
    pub name: &'static str,
    /// Whether it depends on the block's inputs at the same instant
    /// ([`crate::scene::OutputSpec::feedthrough`]): a cycle of such reads is an algebraic loop.
    pub feedthrough: bool,
}

/// A block kind of [`crate::scene::blocks`]: what `model!` needs to check and expand
/// `name = Kind(key = value, …)`.
#[derive(Clone, Copy)]
pub struct BlockKindSpec {
    /// The struct's and the constructor's name (`"PI"`).
    pub name: &'static str,
    /// Its parameters, in the struct's field order.
    pub params: &'static [BlockParam],
    /// Whether the struct implements `Default` (then parameters not given take its values;
    /// else every field is written out, a default from the row).
    pub has_default: bool,
    /// Its input ports, in the block's order.
    pub inputs: &'static [&'static str],
    /// Its outputs, in the block's order. With `numbered_outputs`, the outputs of one axis.
    pub outputs: &'static [BlockOutput],
    /// Whether the outputs are per axis: with several axes they are numbered from 1
    /// (`q1`, `qd1`, `qdd1`, `q2`, …), with one axis as listed (a `PtpPath`).
    pub numbered_outputs: bool,
    /// Its continuous states (signals `<block>.<name>`).
    pub states: &'static [&'static str],
    /// Its discrete states (signals too).
    pub discrete_states: &'static [&'static str],
    /// The block with every parameter at its default, the required ones at a valid value and
    /// the enum-valued ones at the variants chosen: its ports, outputs and states are those of
    /// every block of the kind with these variants (`model!` reads a configured `Drive`'s
    /// from it). With every variant at its default they are the row's lists (the table's test
    /// checks).
    pub example: fn(&BlockVariants<'_>) -> Arc<dyn Component>,
}

impl std::fmt::Debug for BlockKindSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BlockKindSpec")
            .field("name", &self.name)
            .field("params", &self.params)
            .field("inputs", &self.inputs)
            .field("outputs", &self.outputs)
            .field("states", &self.states)
            .field("discrete_states", &self.discrete_states)
            .finish_non_exhaustive()
    }
}

impl BlockKindSpec {
    /// The parameter `key`, if the kind has it.
    pub fn param(&self, key: &str) -> Option<&'static BlockParam> {
        self.params.iter().find(|p| p.key == key)
    }
    /// Every key `model!` accepts: the parameters, then the input ports.
    pub fn keys(&self) -> impl Iterator<Item = &'static str> {
        let (params, inputs) = (self.params, self.inputs);
        params.iter().map(|p| p.key).chain(inputs.iter().copied())
    }
}

const fn num(key: &'static str, default: Option<&'static str>) -> BlockParam {
    BlockParam {
        key,
        value: BlockValue::Number,
        default,
    }
}

const fn out(name: &'static str, feedthrough: bool) -> BlockOutput {
    BlockOutput { name, feedthrough }
}

const Y: &[BlockOutput] = &[out("y", false)];
const Y_THROUGH: &[BlockOutput] = &[out("y", true)];

fn arc(c: impl Component + 'static) -> Arc<dyn Component> {
    Arc::new(c)
}

/// A row for a block whose `Default` is its example.
macro_rules! default_example {
    ($t:ident) => {
        |_| arc(super::blocks::$t::default())
    };
}

/// The block kinds, in the order of `blocks.rs`.
pub static BLOCK_KINDS: &[BlockKindSpec] = &[
    BlockKindSpec {
        name: "Constant",
        params: &[num("k", None)],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Constant),
    },
    BlockKindSpec {
        name: "Step",
        params: &[
            num("height", None),
            num("offset", Some("0")),
            num("startTime", Some("0")),
        ],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Step),
    },
    BlockKindSpec {
        name: "Ramp",
        params: &[
            num("height", None),
            num("duration", None),
            num("offset", Some("0")),
            num("startTime", Some("0")),
        ],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: |_| {
            arc(Ramp {
                height: 1.0,
                duration: 1.0,
                ..Default::default()
            })
        },
    },
    BlockKindSpec {
        name: "Sine",
        params: &[
            num("amplitude", None),
            num("f", None),
            num("phase", Some("0")),
            num("offset", Some("0")),
            num("startTime", Some("0")),
        ],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Sine),
    },
    BlockKindSpec {
        name: "Table",
        params: &[BlockParam {
            key: "table",
            value: BlockValue::Pairs,
            default: None,
        }],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Table),
    },
    BlockKindSpec {
        name: "Input",
        params: &[num("start", Some("0"))],
        has_default: true,
        inputs: &[],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &["value"],
        example: default_example!(Input),
    },
    BlockKindSpec {
        name: "PtpPath",
        params: &[
            BlockParam {
                key: "positions",
                value: BlockValue::Rows,
                default: None,
            },
            BlockParam {
                key: "v_max",
                value: BlockValue::Numbers,
                default: None,
            },
            BlockParam {
                key: "a_max",
                value: BlockValue::Numbers,
                default: None,
            },
            num("startTime", Some("0")),
        ],
        has_default: true,
        inputs: &[],
        outputs: &[out("q", false), out("qd", false), out("qdd", false)],
        numbered_outputs: true,
        states: &[],
        discrete_states: &[],
        example: |_| {
            arc(PtpPath {
                positions: vec![vec![0.0], vec![1.0]],
                v_max: vec![1.0],
                a_max: vec![1.0],
                startTime: 0.0,
            })
        },
    },
    BlockKindSpec {
        name: "Gain",
        params: &[num("k", None)],
        has_default: true,
        inputs: &["u"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: |_| arc(Gain { k: 2.0 }),
    },
    BlockKindSpec {
        name: "Feedback",
        params: &[],
        has_default: true,
        inputs: &["u1", "u2"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Feedback),
    },
    BlockKindSpec {
        name: "Add",
        params: &[num("k1", Some("1")), num("k2", Some("1"))],
        has_default: true,
        inputs: &["u1", "u2"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Add),
    },
    BlockKindSpec {
        name: "Add3",
        params: &[
            num("k1", Some("1")),
            num("k2", Some("1")),
            num("k3", Some("1")),
        ],
        has_default: true,
        inputs: &["u1", "u2", "u3"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: default_example!(Add3),
    },
    BlockKindSpec {
        name: "Limiter",
        params: &[num("uMax", None), num("uMin", Some("-uMax"))],
        has_default: false,
        inputs: &["u"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &[],
        discrete_states: &["mode"],
        example: |_| arc(Limiter::new(-1.0, 1.0)),
    },
    BlockKindSpec {
        name: "Integrator",
        params: &[num("k", Some("1")), num("y_start", Some("0"))],
        has_default: true,
        inputs: &["u"],
        outputs: Y,
        numbered_outputs: false,
        states: &["x"],
        discrete_states: &[],
        example: default_example!(Integrator),
    },
    BlockKindSpec {
        name: "FirstOrder",
        params: &[
            num("k", Some("1")),
            num("T", None),
            num("y_start", Some("0")),
        ],
        has_default: true,
        inputs: &["u"],
        outputs: Y,
        numbered_outputs: false,
        states: &["x"],
        discrete_states: &[],
        example: default_example!(FirstOrder),
    },
    BlockKindSpec {
        name: "PI",
        params: &[
            num("k", Some("1")),
            num("T", None),
            num("x_start", Some("0")),
        ],
        has_default: true,
        inputs: &["u"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &["x"],
        discrete_states: &[],
        example: |_| arc(PI::new(1.0, 1.0)),
    },
    BlockKindSpec {
        name: "PID",
        params: &[
            num("k", Some("1")),
            num("Ti", None),
            num("Td", None),
            num("Nd", Some("10")),
            num("xi_start", Some("0")),
            num("xd_start", Some("0")),
        ],
        has_default: true,
        inputs: &["u"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &["xi", "xd"],
        discrete_states: &[],
        example: default_example!(PID),
    },
    BlockKindSpec {
        name: "LimPID",
        params: &[
            num("k", Some("1")),
            num("Ti", None),
            num("Td", None),
            num("yMax", None),
            num("yMin", Some("-yMax")),
            num("wp", Some("1")),
            num("wd", Some("0")),
            num("Ni", Some("0.9")),
            num("Nd", Some("10")),
            num("xi_start", Some("0")),
            num("xd_start", Some("0")),
        ],
        has_default: true,
        inputs: &["u_s", "u_m"],
        outputs: Y_THROUGH,
        numbered_outputs: false,
        states: &["xi", "xd"],
        discrete_states: &["mode"],
        example: default_example!(LimPID),
    },
    BlockKindSpec {
        name: "Sampled",
        params: &[
            num("period", None),
            num("startTime", Some("0")),
            BlockParam {
                key: "inner",
                value: BlockValue::Block,
                default: None,
            },
        ],
        has_default: false,
        // The inner block's ports, outputs without feedthrough; discrete states `tick`, the
        // inner states and `<output>_held`: listed here for the default example's inner
        // block (a `Gain`), `example` with `inner` chosen for the others.
        inputs: &["u"],
        outputs: Y,
        numbered_outputs: false,
        states: &[],
        discrete_states: &["tick", "y_held"],
        example: |v| {
            let inner = v("inner")
                .and_then(block_kind)
                .map_or_else(|| arc(Gain { k: 2.0 }), |k| (k.example)(&|_| None));
            arc(Sampled {
                period: 0.001,
                startTime: 0.0,
                inner,
            })
        },
    },
    BlockKindSpec {
        name: "Drive",
        params: &[
            BlockParam {
                key: "joint",
                value: BlockValue::Joint,
                default: None,
            },
            BlockParam {
                key: "coordinate",
                value: BlockValue::Coordinate,
                default: Some("the joint's only scalar coordinate"),
            },
            num("ratio", None),
            num("J_motor", None),
            BlockParam {
                key: "gear",
                value: BlockValue::Variant(&[
                    BlockVariant {
                        name: "Rigid",
                        fields: &[],
                    },
                    BlockVariant {
                        name: "Elastic",
                        fields: &["c", "d"],
                    },
                ]),
                default: Some("Rigid"),
            },
            BlockParam {
                key: "motor",
                value: BlockValue::Variant(&[
                    BlockVariant {
                        name: "Torque",
                        fields: &[],
                    },
                    BlockVariant {
                        name: "Dc",
                        fields: &["R", "L", "k"],
                    },
                ]),
                default: Some("Torque"),
            },
        ],
        has_default: false,
        // A torque source on a rigid gear; an elastic gear adds states `phi_gear`, `motor_w`
        // (and `tau_load` loses its feedthrough), a DC motor takes `v` instead of `tau` and
        // adds the current `i` (`example` with the variants chosen).
        inputs: &["tau"],
        outputs: &[
            out("motor_phi", false),
            out("motor_w", false),
            out("tau_motor", true),
            out("tau_load", true),
        ],
        numbered_outputs: false,
        states: &[],
        discrete_states: &[],
        example: |v| {
            let mut d = Drive::rigid("rev", 100.0, 1e-5);
            if v("gear") == Some("Elastic") {
                d = d.elastic(1e3, 1.0);
            }
            if v("motor") == Some("Dc") {
                d = d.dc_motor(1.0, 1e-3, 0.1);
            }
            arc(d)
        },
    },
];

/// The row of block kind `name`, if it is one.
pub fn block_kind(name: &str) -> Option<&'static BlockKindSpec> {
    BLOCK_KINDS.iter().find(|k| k.name == name)
}
