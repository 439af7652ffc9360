//! A steel sphere (Ø 0.1 m) dropped from 0.5 m onto a fixed steel box (Steel–Steel: cor 0.7).
//! Prints the events (contact start/end) and the apex heights, which fall by about cor² per
//! bounce, and that the sphere comes to rest after finitely many events.

use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("table")
                .parent("world")
                .translation([0.0, 0.0, -0.05])
                .solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(1.0, 1.0, 0.1),
                    })
                    .material("Steel")
                    .collision(true),
                ),
        )
        .add(
            Object3D::new("ball").solid(
                Solid::new(Shape::Sphere { diameter: 0.1 })
                    .material("Steel")
                    .collision(true),
            ),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "ball",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 0.55),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    let model = scene.build()?;
    let res = model.simulate(&SimOptions::new(3.0).tolerance(1e-6).interval(1e-3))?;
    for e in res.events.iter().take(8) {
        println!("t = {:.6} s: {}", e.t, e.description);
    }
    let z = res.signal("ball.r_abs[2]")?;
    println!(
        "{} events; final height {:.7} m (radius 0.05 m); stats: {} steps, {} root functions, {} narrow-phase calls, wall {:.3} s",
        res.events.len(),
        z.last()[0],
        res.stats.solver.steps,
        res.stats.root_functions,
        res.stats.narrow_phase_calls,
        res.stats.wall_time
    );
    Ok(())
}
