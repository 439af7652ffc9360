//! A machine block (20 kg) on four rubber bushings, with an unbalanced rotor: the block is
//! released with unloaded mounts, sags under gravity and settles, while the rotor's rotating
//! force (a `WorldForce` closure of time) shakes it. Prints the static sag beside the root of
//! `k_z δ + k3 δ³ = m g / 4`, the bounce frequency beside the damped frequency of the tangent
//! stiffness `k_z + 3 k3 δ²` there, and the largest bushing force.

use modia3d::prelude::*;

model! {
    /// A 0.4 × 0.3 × 0.2 m block of mass `mass` \[kg\] on four bushings at its bottom corners
    /// (stiffness `kz` [N/m] vertically, `kxy` horizontally); an unbalance `me` [kg·m] at
    /// `omega` [rad/s].
    pub MachineMount(mass: f64 = 20.0, kz: f64 = 5.0e4, kxy: f64 = 2.0e4, me: f64 = 1.0e-3,
                     omega: f64 = 300.0) {
        world = Object3D(feature = Scene(gravity = [0, 0, -9.81])),
        block = Object3D(feature = Solid(shape = Box(lengths = [0.4, 0.3, 0.2]),
                                         mass_properties = MassProperties(mass = mass))),
        free  = FreeMotion(obj1 = world, obj2 = block),
        // The feet (on the block) and the mounts (on the floor) coincide at the start.
        foot1  = Object3D(parent = block, translation = [0.2, 0.15, -0.1]),
        foot2  = Object3D(parent = block, translation = [-0.2, 0.15, -0.1]),
        foot3  = Object3D(parent = block, translation = [-0.2, -0.15, -0.1]),
        foot4  = Object3D(parent = block, translation = [0.2, -0.15, -0.1]),
        mount1 = Object3D(parent = world, translation = [0.2, 0.15, -0.1]),
        mount2 = Object3D(parent = world, translation = [-0.2, 0.15, -0.1]),
        mount3 = Object3D(parent = world, translation = [-0.2, -0.15, -0.1]),
        mount4 = Object3D(parent = world, translation = [0.2, -0.15, -0.1]),
        // Rubber stiffens in compression: a cubic term on the vertical spring law.
        b1 = Bushing(obj1 = mount1, obj2 = foot1, spring_law = [kxy, kxy, |z| kz * z + 1e9 * z * z * z],
                     damper_law = [50, 50, 100], rot_spring_law = [20, 20, 20]),
        b2 = Bushing(obj1 = mount2, obj2 = foot2, spring_law = [kxy, kxy, |z| kz * z + 1e9 * z * z * z],
                     damper_law = [50, 50, 100], rot_spring_law = [20, 20, 20]),
        b3 = Bushing(obj1 = mount3, obj2 = foot3, spring_law = [kxy, kxy, |z| kz * z + 1e9 * z * z * z],
                     damper_law = [50, 50, 100], rot_spring_law = [20, 20, 20]),
        b4 = Bushing(obj1 = mount4, obj2 = foot4, spring_law = [kxy, kxy, |z| kz * z + 1e9 * z * z * z],
                     damper_law = [50, 50, 100], rot_spring_law = [20, 20, 20]),
        // The rotor's unbalance: me ω² turning in the x-z plane, switched on after 1 s.
        imbalance = WorldForce(object = block, force = |t, _| {
            let f = if t < 1.0 { 0.0 } else { me * omega * omega };
            Vector3::new(f * (omega * t).cos(), 0.0, f * (omega * t).sin())
        }),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mount = MachineMount::default();
    let (m, kz) = (mount.mass, mount.kz);
    let model = mount.build()?;
    let res = model.simulate(&SimOptions::new(1.5).tolerance(1e-8).interval(5e-4))?;
    let (t, z) = (res.time(), res.signal("block.r_abs[2]")?.values());
    // Static sag: where the settled block rests (t = 1 s, before the rotor starts), against
    // the root of k_z δ + k3 δ³ = m g / 4 (Newton from the linear sag).
    let k3 = 1e9;
    let mut delta = m * 9.81 / (4.0 * kz);
    for _ in 0..20 {
        delta -=
            (kz * delta + k3 * delta.powi(3) - m * 9.81 / 4.0) / (kz + 3.0 * k3 * delta * delta);
    }
    let k_settled = t.iter().position(|&x| x >= 1.0).ok_or("no output at 1 s")?;
    let sag = -z[k_settled];
    println!(
        "static sag {:.4} mm (closed form {:.4} mm; linear spring alone {:.4} mm)",
        sag * 1e3,
        delta * 1e3,
        m * 9.81 / (4.0 * kz) * 1e3
    );
    // Bounce frequency from the first two upward crossings of the settled level.
    let ups: Vec<f64> = (1..k_settled)
        .filter(|&k| z[k - 1] < -sag && z[k] >= -sag)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * (-sag - z[k - 1]) / (z[k] - z[k - 1]))
        .collect();
    if let [a, b, ..] = ups.as_slice() {
        // Small oscillations about the sag: tangent stiffness, 4 × 100 N·s/m damping.
        let kt = 4.0 * (kz + 3.0 * k3 * delta * delta);
        let zeta = 4.0 * 100.0 / (2.0 * (kt * m).sqrt());
        let fd = (kt / m).sqrt() * (1.0 - zeta * zeta).sqrt() / (2.0 * std::f64::consts::PI);
        println!(
            "bounce {:.2} Hz (damped frequency of the tangent stiffness {fd:.2} Hz)",
            1.0 / (b - a)
        );
    }
    let f = res.signal("b1.force")?;
    let fmax = (0..t.len())
        .map(|k| f.at(k).map_or(0.0, |x| x[2].abs()))
        .fold(0.0, f64::max);
    let late = z[k_settled..]
        .iter()
        .map(|x| (x + sag).abs())
        .fold(0.0, f64::max);
    println!(
        "largest vertical force in one bushing {fmax:.1} N; rotor shakes the block by ±{:.3} mm",
        late * 1e3
    );
    println!("steps {}", res.stats.solver.steps);
    Ok(())
}
