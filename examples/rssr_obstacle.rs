//! A spatial RSSR linkage hitting an obstacle: a crank turning about the world's z axis, a
//! coupler on a spherical joint at the crank's tip, and a rocker turning about the world's x
//! axis, whose tip is joined to the coupler's by a second spherical joint, `close` (the cut
//! joint: three position constraints). A steel ball on the rocker's tip strikes a steel wall
//! on each swing; every impact is an event after which the loop is re-projected. Written with
//! the builder API: `model!` has no vocabulary for spherical joints yet.

use modia3d::prelude::*;

/// Crank 0.05 m, coupler 0.374 m, rocker 0.2 m, the rocker's pivot at (0.3, 0, 0.3) m; the crank
/// starts at π rad and 6 rad/s (the build closes the loop on the rocker's branch at y < 0);
/// under gravity the linkage rocks, the rocker's ball between y ≈ −0.066 and −0.078 m. The
/// wall fills y < `wall_y` [m] below the ball.
pub fn rssr(wall_y: f64) -> SceneDesc {
    let (a, b, c, w) = (0.05, 0.14f64.sqrt(), 0.2, 0.01);
    let bar = |name: &str, parent: &str, lengths: [f64; 3], at: [f64; 3]| {
        Object3D::new(name).parent(parent).translation(at).solid(
            Solid::new(Shape::Box {
                lengths: Vector3::from(lengths),
            })
            .material("Steel"),
        )
    };
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("rocker_pivot")
                .parent("world")
                .translation([0.3, 0.0, 0.3]),
        )
        .add(
            Object3D::new("wall")
                .parent("world")
                .translation([0.3, wall_y - 0.05, 0.2])
                .solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(0.2, 0.1, 0.2),
                    })
                    .material("Steel")
                    .collision(true),
                ),
        )
        .add(Object3D::new("crank"))
        .add(bar("crank_bar", "crank", [a, w, w], [a / 2.0, 0.0, 0.0]))
        .add(
            Object3D::new("crank_tip")
                .parent("crank")
                .translation([a, 0.0, 0.0]),
        )
        .add(Object3D::new("coupler"))
        .add(bar(
            "coupler_bar",
            "coupler",
            [b, w, w],
            [b / 2.0, 0.0, 0.0],
        ))
        .add(
            Object3D::new("coupler_tip")
                .parent("coupler")
                .translation([b, 0.0, 0.0]),
        )
        .add(Object3D::new("rocker"))
        .add(bar("rocker_bar", "rocker", [w, w, c], [0.0, 0.0, -c / 2.0]))
        .add(
            Object3D::new("rocker_tip")
                .parent("rocker")
                .translation([0.0, 0.0, -c])
                .solid(
                    Solid::new(Shape::Sphere { diameter: 0.04 })
                        .material("Steel")
                        .collision(true),
                ),
        )
        .add_joint(
            Joint::new("crank_joint", "world", "crank", JointKind::revolute(3))
                .init_position(std::f64::consts::PI)
                .init_velocity(6.0),
        )
        .add_joint(Joint::new(
            "coupler_joint",
            "crank_tip",
            "coupler",
            // A rough guess of the coupler's direction; the build closes the loop.
            JointKind::Spherical {
                rot: FreeRotation::Cardan([0.0, -0.3, -2.9]),
                w: Vector3::zeros(),
            },
        ))
        .add_joint(
            // The wall is part of the world, which this joint holds: let them collide.
            Joint::new(
                "rocker_joint",
                "rocker_pivot",
                "rocker",
                JointKind::revolute(1),
            )
            .init_position(0.4)
            .can_collide(true),
        )
        .add_joint(
            Joint::new("close", "coupler_tip", "rocker_tip", JointKind::spherical()).cut(true),
        );
    s
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = rssr(-0.09).build()?;
    println!("loops: {:?}", model.loops());
    println!(
        "pairs: {:?}",
        model
            .contact_pairs()
            .iter()
            .map(|p| p.name.clone())
            .collect::<Vec<_>>()
    );
    println!(
        "independent coordinates: {:?}",
        model.independent_coordinates()
    );
    let result = model.simulate(&SimOptions::new(2.0).tolerance(1e-6).interval(0.01))?;
    let y = result.signal("rocker_tip.r_abs[1]")?.values();
    println!(
        "rocker tip y in [{:.4}, {:.4}] m",
        y.iter().cloned().fold(f64::INFINITY, f64::min),
        y.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
    );
    for e in &result.events {
        println!("{:8.4} s  {}", e.t, e.description);
    }
    let s = &result.stats.solver;
    println!(
        "{} events, steps {}, wall time {:.3} s",
        result.events.len(),
        s.steps,
        result.stats.wall_time
    );
    Ok(())
}
