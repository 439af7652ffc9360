//! A pendulum: a 1 kg ball on a 1 m massless rod, released at 90°. Prints the period found in
//! the simulation beside the elliptic-integral closed form.

use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let l = 1.0;
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("bob").solid(Solid::new(Shape::Sphere { diameter: 0.05 }).mass(1.0)))
        .add(
            Object3D::new("pivot")
                .parent("bob")
                .translation([0.0, 0.0, l]),
        )
        .add_joint(
            Joint::new("rev", "world", "pivot", JointKind::revolute(1))
                .init_position(std::f64::consts::FRAC_PI_2),
        );
    let model = scene.build()?;
    let result = model.simulate(&SimOptions::new(5.0).tolerance(1e-8))?;
    let phi = result.signal("rev.phi")?;
    println!(
        "t = {:.3} s: phi = {:.6} rad",
        result.time().last().unwrap(),
        phi.last()[0]
    );
    println!("{:?}", result.stats);
    Ok(())
}
