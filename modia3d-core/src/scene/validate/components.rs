//! The components of a scene checked and resolved: parameters, names, every input port wired
//! once to a signal that exists, flanges on scalar coordinates of tree joints, and an order of
//! evaluation without algebraic loops (a cycle of same-instant reads with no state in it).

use super::error::SceneError;
use super::{did_you_mean, Checker, Names, ValidJoint};
use crate::scene::components::{Component, Src, SrcFn};
use crate::scene::SceneDesc;
use std::collections::HashMap;
use std::sync::Arc;

/// A signal a component input reads, resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SigRef {
    /// Time \[s\].
    Time,
    /// Output `k` of component `c`.
    Output(usize, usize),
    /// Continuous state `k` of component `c`.
    State(usize, usize),
    /// Discrete state `k` of component `c`.
    Discrete(usize, usize),
    /// Position of scalar coordinate `k` of joint `j` (index into `ValidScene::joints`).
    JointPos(usize, usize),
    /// Velocity of that coordinate.
    JointVel(usize, usize),
    /// Acceleration of that coordinate (`der(<joint>.<velocity>)`).
    JointAcc(usize, usize),
}

/// Where a resolved input's value comes from.
#[derive(Clone)]
pub(crate) enum ValidSrc {
    Const(f64),
    Ref(SigRef),
    Expr(Vec<SigRef>, Arc<SrcFn>),
}

impl std::fmt::Debug for ValidSrc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ValidSrc::Const(v) => write!(f, "Const({v})"),
            ValidSrc::Ref(r) => write!(f, "Ref({r:?})"),
            ValidSrc::Expr(d, _) => write!(f, "Expr({d:?})"),
        }
    }
}

/// A checked component.
#[derive(Clone, Debug)]
pub(crate) struct ValidComponent {
    pub name: String,
    pub component: Arc<dyn Component>,
    /// Per input port (in the component's order), its source.
    pub inputs: Vec<ValidSrc>,
    /// Per flange: joint (index into `ValidScene::joints`), coordinate index, reflected
    /// inertia.
    pub flanges: Vec<(usize, usize, f64)>,
    /// Names, units, starts and nominal sizes of its states, outputs and discrete states.
    pub states: Vec<crate::scene::StateSpec>,
    pub outputs: Vec<crate::scene::OutputSpec>,
    pub discrete: Vec<crate::scene::StateSpec>,
    pub n_crossings: usize,
}

/// The checked components and an order of evaluation in which every same-instant read of an
/// output (feedthrough) follows its writer.
#[derive(Clone, Debug, Default)]
pub(crate) struct ValidComponents {
    pub list: Vec<ValidComponent>,
    pub order: Vec<usize>,
}

/// Checks `desc.components` against the joints and the cut joints of the topology.
pub(super) fn components(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    joints: &[ValidJoint],
    cut_joints: &[usize],
) -> ValidComponents {
    let decls = &desc.components;
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (i, d) in decls.iter().enumerate() {
        let clash = names.joint_index.contains_key(d.name.as_str())
            || desc.objects.iter().any(|o| o.name == d.name);
        if index.insert(d.name.as_str(), i).is_some() || clash || d.name == "time" {
            c.errors.push(SceneError::DuplicateName {
                kind: "component",
                name: d.name.clone(),
            });
        }
    }
    let specs: Vec<_> = decls
        .iter()
        .map(|d| {
            let comp = &d.component;
            (
                comp.inputs(),
                comp.outputs(),
                comp.states(),
                comp.discrete_states(),
            )
        })
        .collect();
    let joint_valid = |name: &str| joints.iter().position(|vj| vj.name == name);
    // Every signal path a component can read, for hints.
    let mut all_paths: Vec<String> = vec!["time".into()];
    for (d, (_, outs, xs, ds)) in decls.iter().zip(&specs) {
        for n in outs
            .iter()
            .map(|o| &o.name)
            .chain(xs.iter().map(|x| &x.name))
            .chain(ds.iter().map(|x| &x.name))
        {
            all_paths.push(format!("{}.{n}", d.name));
        }
    }
    for j in &desc.joints {
        for (p, v) in j.kind.facts().spec.coordinate_signals() {
            all_paths.push(format!("{}.{p}", j.name));
            all_paths.push(format!("{}.{v}", j.name));
        }
    }
    let mut list = vec![];
    for (d, (ports, outs, xs, ds)) in decls.iter().zip(&specs) {
        let kind = d.component.kind();
        if let Err(reason) = d.component.check() {
            c.errors.push(SceneError::ComponentParameter {
                component: d.name.clone(),
                kind,
                reason,
            });
        }
        for x in xs.iter().chain(ds) {
            if !(x.start.is_finite() && x.nominal.is_finite() && x.nominal > 0.0) {
                c.errors.push(SceneError::ComponentParameter {
                    component: d.name.clone(),
                    kind,
                    reason: format!(
                        "state `{}` starts at {} with nominal size {}: both must be finite and the nominal size positive",
                        x.name, x.start, x.nominal
                    ),
                });
            }
        }
        let mut sources: Vec<Option<ValidSrc>> = vec![None; ports.len()];
        let port_list = || {
            let v: Vec<String> = ports.iter().map(|p| format!("`{}`", p.name)).collect();
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        let mut cut_used = false;
        for (port, src) in &d.inputs {
            let Some(k) = ports.iter().position(|p| &p.name == port) else {
                c.errors.push(SceneError::UnknownPort {
                    component: d.name.clone(),
                    kind,
                    port: port.clone(),
                    ports: port_list(),
                });
                continue;
            };
            if sources[k].is_some() {
                c.errors.push(SceneError::UnknownPort {
                    component: d.name.clone(),
                    kind,
                    port: port.clone(),
                    ports: port_list(),
                });
                continue;
            }
            let mut resolve = |path: &str| -> Option<SigRef> {
                if path == "time" {
                    return Some(SigRef::Time);
                }
                // `der(<joint>.<velocity>)`: a coordinate's acceleration.
                let (path, der) = match path.strip_prefix("der(").and_then(|p| p.strip_suffix(')'))
                {
                    Some(inner) => (inner, true),
                    None => (path, false),
                };
                let found = path.rsplit_once('.').and_then(|(owner, field)| {
                    if let Some(&oc) = index.get(owner) {
                        let (_, outs, xs, ds) = &specs[oc];
                        if let Some(k) = outs.iter().position(|o| o.name == field) {
                            return Some(SigRef::Output(oc, k));
                        }
                        if let Some(k) = xs.iter().position(|o| o.name == field) {
                            return Some(SigRef::State(oc, k));
                        }
                        if let Some(k) = ds.iter().position(|o| o.name == field) {
                            return Some(SigRef::Discrete(oc, k));
                        }
                        return None;
                    }
                    let ji = *names.joint_index.get(owner)?;
                    let sigs: Vec<_> = desc.joints[ji]
                        .kind
                        .facts()
                        .spec
                        .coordinate_signals()
                        .collect();
                    let vj = joint_valid(owner)?;
                    if cut_joints.contains(&vj) {
                        cut_used = true;
                    }
                    for (k, (p, v)) in sigs.iter().enumerate() {
                        if *p == field && !der {
                            return Some(SigRef::JointPos(vj, k));
                        }
                        if *v == field {
                            return Some(if der {
                                SigRef::JointAcc(vj, k)
                            } else {
                                SigRef::JointVel(vj, k)
                            });
                        }
                    }
                    None
                });
                let found = found.filter(|r| !der || matches!(r, SigRef::JointAcc(..)));
                if found.is_none() {
                    c.errors.push(SceneError::UnknownSignal {
                        component: d.name.clone(),
                        port: port.clone(),
                        path: if der {
                            format!("der({path})")
                        } else {
                            path.to_string()
                        },
                        hint: did_you_mean(path, all_paths.iter().map(String::as_str)),
                    });
                }
                found
            };
            sources[k] = match src {
                Src::Const(v) => {
                    if !v.is_finite() {
                        c.errors.push(SceneError::ComponentParameter {
                            component: d.name.clone(),
                            kind,
                            reason: format!(
                                "input `{port}` is the constant {v}: give a finite value"
                            ),
                        });
                    }
                    Some(ValidSrc::Const(*v))
                }
                Src::Signal(p) => resolve(p).map(ValidSrc::Ref),
                Src::Expr { deps, f } => {
                    let r: Vec<_> = deps.iter().map(|p| resolve(p)).collect();
                    r.into_iter()
                        .collect::<Option<Vec<_>>>()
                        .map(|r| ValidSrc::Expr(r, f.clone()))
                }
            };
        }
        for (k, s) in sources.iter().enumerate() {
            if s.is_none() && !d.inputs.iter().any(|(p, _)| *p == ports[k].name) {
                c.errors.push(SceneError::UnwiredInput {
                    component: d.name.clone(),
                    kind,
                    port: ports[k].name.clone(),
                });
            }
        }
        let mut flanges = vec![];
        for f in d.component.flanges() {
            let referrer = format!("component `{}`'s flange", d.name);
            if let Some((j, k)) = super::forces::joint_coordinate(
                c,
                desc,
                names,
                joints,
                &referrer,
                &f.joint,
                &f.coordinate,
            ) {
                if cut_joints.contains(&j) {
                    cut_used = true;
                }
                if !(f.inertia.is_finite() && f.inertia >= 0.0) {
                    c.errors.push(SceneError::ComponentParameter {
                        component: d.name.clone(),
                        kind,
                        reason: format!(
                            "the flange's reflected inertia {} must be finite and ≥ 0",
                            f.inertia
                        ),
                    });
                }
                flanges.push((j, k, f.inertia));
            }
        }
        if cut_used {
            c.errors.push(SceneError::ComponentOnCutJoint {
                component: d.name.clone(),
                joint: d
                    .component
                    .flanges()
                    .first()
                    .map_or_else(String::new, |f| f.joint.clone()),
            });
        }
        list.push(ValidComponent {
            name: d.name.clone(),
            component: d.component.clone(),
            inputs: sources
                .into_iter()
                .map(|s| s.unwrap_or(ValidSrc::Const(0.0)))
                .collect(),
            flanges,
            states: xs.clone(),
            outputs: outs.clone(),
            discrete: ds.clone(),
            n_crossings: d.component.n_crossings(),
        });
    }
    let order = evaluation_order(c, &list);
    ValidComponents { list, order }
}

/// The components in an order where each one with a feedthrough output comes after every
/// component whose feedthrough output it reads (Kahn's algorithm); a cycle is an algebraic
/// loop, reported with its members.
fn evaluation_order(c: &mut Checker, list: &[ValidComponent]) -> Vec<usize> {
    let n = list.len();
    let mut preds: Vec<Vec<usize>> = vec![vec![]; n];
    for (b, comp) in list.iter().enumerate() {
        if !comp.outputs.iter().any(|o| o.feedthrough) {
            continue;
        }
        for src in &comp.inputs {
            let refs: &[SigRef] = match src {
                ValidSrc::Const(_) => &[],
                ValidSrc::Ref(r) => std::slice::from_ref(r),
                ValidSrc::Expr(r, _) => r,
            };
            for r in refs {
                if let SigRef::Output(a, k) = *r {
                    if list[a].outputs[k].feedthrough && !preds[b].contains(&a) {
                        preds[b].push(a);
                    }
                }
            }
        }
    }
    let mut indeg: Vec<usize> = preds.iter().map(Vec::len).collect();
    let mut succ: Vec<Vec<usize>> = vec![vec![]; n];
    for (b, p) in preds.iter().enumerate() {
        for &a in p {
            succ[a].push(b);
        }
    }
    let mut ready: Vec<usize> = (0..n).rev().filter(|&i| indeg[i] == 0).collect();
    let mut order = vec![];
    while let Some(i) = ready.pop() {
        order.push(i);
        for &s in succ[i].iter().rev() {
            indeg[s] -= 1;
            if indeg[s] == 0 {
                ready.push(s);
            }
        }
    }
    if order.len() < n {
        // Walk back along predecessors still unordered until a member repeats: a cycle.
        let start = (0..n).find(|&i| indeg[i] > 0).unwrap_or(0);
        let mut path = vec![start];
        let mut at = start;
        while let Some(&p) = preds[at].iter().find(|&&p| indeg[p] > 0) {
            if let Some(pos) = path.iter().position(|&x| x == p) {
                path.drain(..pos);
                break;
            }
            path.push(p);
            at = p;
        }
        path.reverse();
        c.errors.push(SceneError::AlgebraicLoop {
            cycle: path.iter().map(|&i| list[i].name.clone()).collect(),
        });
    }
    order
}
