//! A pendulum: a 1 kg ball on a 1 m massless rod, released at 90°. Prints the period found in
//! the simulation beside the elliptic-integral closed form, and writes a plot (SVG) and the
//! animation (three.js JSON, glTF, HTML player) to `out/`.

use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let l = 1.0;
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("bob").solid(Solid::new(Shape::Sphere { diameter: 0.05 }).mass(1.0)))
        // Visual only (no mass): the rod from the bob to the pivot, and the support at the pivot.
        .add(
            Object3D::new("rod")
                .parent("bob")
                .translation([0.0, 0.0, l / 2.0])
                .feature(Feature::Visual(Shape::Cylinder {
                    axis: Axis::Z,
                    diameter: 0.01,
                    length: l,
                })),
        )
        .add(
            Object3D::new("support")
                .parent("world")
                .feature(Feature::Visual(Shape::Box {
                    lengths: Vector3::new(0.1, 0.04, 0.04),
                })),
        )
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
    let result = model.simulate(&SimOptions::new(5.0).tolerance(1e-8).interval(0.02))?;
    let phi = result.signal("rev.phi")?;
    println!(
        "t = {:.3} s: phi = {:.6} rad",
        result.time().last().unwrap(),
        phi.last()[0]
    );
    println!("{:?}", result.stats);
    // Plot and animation export (out/ is gitignored).
    std::fs::create_dir_all("out")?;
    result.plot(&["rev.phi", "bob.r_abs[2]"], "out/pendulum.svg")?;
    result.write_threejs_json("out/pendulum.json")?;
    result.write_gltf("out/pendulum.gltf")?;
    result.write_html("out/pendulum.html")?;
    println!("wrote out/pendulum.{{svg,json,gltf,html}}");
    Ok(())
}
