//! Signals of named force elements, computed on demand from the stored states with the same
//! functions the residual uses (`dynamics/forces.rs`): a point-to-point spring-damper's
//! `length` \[m\], `length_rate` [m/s] and `tension` \[N\]; a bushing's `r` \[m\], `v` [m/s],
//! `angles` \[rad\], `rates` [rad/s], `force` \[N\] and `torque` [N·m] (on obj2, all resolved
//! in obj1); a `WorldForce`'s `force` \[N\] and a `WorldTorque`'s `torque` [N·m], resolved in
//! world.

use super::{Signal, SimulationResult};
use crate::dynamics::{forces, kinematics, Workspace};
use crate::scene::ValidForce;

/// Fields of a point-to-point spring-damper: name, dimension, unit.
const PTP_FIELDS: &[(&str, usize, &str)] = &[
    ("length", 1, "m"),
    ("length_rate", 1, "m/s"),
    ("tension", 1, "N"),
];

/// Fields of a bushing.
const BUSHING_FIELDS: &[(&str, usize, &str)] = &[
    ("r", 3, "m"),
    ("v", 3, "m/s"),
    ("angles", 3, "rad"),
    ("rates", 3, "rad/s"),
    ("force", 3, "N"),
    ("torque", 3, "N·m"),
];

/// Fields of a `WorldForce` and a `WorldTorque`.
const FORCE_FIELDS: &[(&str, usize, &str)] = &[("force", 3, "N")];
const TORQUE_FIELDS: &[(&str, usize, &str)] = &[("torque", 3, "N·m")];

/// The signal fields of a force element (none for unnamed elements).
pub(super) fn fields(f: &ValidForce) -> &'static [(&'static str, usize, &'static str)] {
    match f {
        ValidForce::SpringDamper { .. } => PTP_FIELDS,
        ValidForce::Bushing { .. } => BUSHING_FIELDS,
        ValidForce::WorldVector { torque: false, .. } => FORCE_FIELDS,
        ValidForce::WorldVector { torque: true, .. } => TORQUE_FIELDS,
        _ => &[],
    }
}

impl SimulationResult {
    /// `<element>.<field>` of the force element named `owner`, at every output point; a state
    /// where the element is undefined (a run that stopped there) gives NaN.
    pub(super) fn force_signal(&self, owner: &str, field: &str) -> Option<Signal> {
        let plan = &*self.model.plan;
        let f = plan.scene.forces.iter().find(|f| f.name() == Some(owner))?;
        let &(_, dim, unit) = fields(f).iter().find(|(n, ..)| *n == field)?;
        let mut ws = Workspace::new(plan);
        let mut data = Vec::with_capacity(dim * self.time.len());
        for (&t, y) in self.time.iter().zip(self.states_iter()) {
            let (q, v) = y.split_at(plan.nq);
            kinematics::position_velocity(plan, &mut ws, q, v);
            match f {
                ValidForce::SpringDamper {
                    obj1,
                    obj2,
                    spring,
                    damper,
                    length0,
                    ..
                } => {
                    let s =
                        forces::ptp_state(plan, &ws, (*obj1, *obj2), (spring, damper), *length0);
                    data.push(s.map_or(f64::NAN, |s| match field {
                        "length" => s.length,
                        "length_rate" => s.rate,
                        _ => s.tension,
                    }));
                }
                ValidForce::Bushing { obj1, obj2, spec } => {
                    let s = forces::bushing_state(plan, &ws, *obj1, *obj2, spec);
                    let x = s.map_or(nalgebra::Vector3::repeat(f64::NAN), |(s, ..)| match field {
                        "r" => s.r,
                        "v" => s.v,
                        "angles" => s.angles,
                        "rates" => s.rates,
                        "force" => s.force,
                        _ => s.torque,
                    });
                    data.extend_from_slice(x.as_slice());
                }
                ValidForce::WorldVector {
                    object,
                    value,
                    resolved_in,
                    ..
                } => {
                    let x = forces::world_vector(plan, &ws, t, (*object, *resolved_in), value)
                        .map_or(nalgebra::Vector3::repeat(f64::NAN), |(x, _)| x);
                    data.extend_from_slice(x.as_slice());
                }
                _ => return None,
            }
        }
        Some(Signal {
            name: format!("{owner}.{field}"),
            unit,
            dim,
            data,
        })
    }

    /// `<element>.<field>` names of every named force element's signals.
    pub(super) fn force_signal_names(&self) -> impl Iterator<Item = String> + '_ {
        self.model.plan.scene.forces.iter().flat_map(|f| {
            let name = f.name().unwrap_or_default();
            let fields = if name.is_empty() { &[][..] } else { fields(f) };
            fields.iter().map(move |(n, ..)| format!("{name}.{n}"))
        })
    }
}
