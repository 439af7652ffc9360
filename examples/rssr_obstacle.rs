//! A spatial RSSR linkage hitting an obstacle: a crank turning about the world's z axis, a
//! coupler on a spherical joint at the crank's tip, and a rocker turning about the world's x
//! axis, whose tip is joined to the coupler's by a second spherical joint, `close` (the cut
//! joint: three position constraints). A steel ball on the rocker's tip strikes a steel wall
//! on each swing; every impact is an event after which the loop is re-projected.

use modia3d::prelude::*;

model! {
    /// Crank 0.05 m, coupler 0.374 m (√0.14), rocker 0.2 m, the rocker's pivot at (0.3, 0, 0.3) m;
    /// steel bars `w` × `w`. The crank starts at π rad and 6 rad/s (the build closes the loop on
    /// the rocker's branch at y < 0); under gravity the linkage rocks, the rocker's ball between
    /// y ≈ −0.066 and −0.078 m. The wall fills y < `wall_y` [m] below the ball.
    pub Rssr(wall_y: f64 = -0.09, a: f64 = 0.05, b: f64 = 0.14f64.sqrt(), c: f64 = 0.2,
             w: f64 = 0.01) {
        world        = Object3D(feature = Scene()),
        rocker_pivot = Object3D(parent = world, translation = [0.3, 0.0, 0.3]),
        wall         = Object3D(parent = world, translation = [0.3, wall_y - 0.05, 0.2],
                                feature = Solid(shape = Box(lengths = [0.2, 0.1, 0.2]),
                                                solid_material = "Steel", collision = true)),
        crank        = Object3D(),
        crank_bar    = Object3D(parent = crank, translation = [a / 2.0, 0.0, 0.0],
                                feature = Solid(shape = Box(lengths = [a, w, w]), solid_material = "Steel")),
        crank_tip    = Object3D(parent = crank, translation = [a, 0.0, 0.0]),
        coupler      = Object3D(),
        coupler_bar  = Object3D(parent = coupler, translation = [b / 2.0, 0.0, 0.0],
                                feature = Solid(shape = Box(lengths = [b, w, w]), solid_material = "Steel")),
        coupler_tip  = Object3D(parent = coupler, translation = [b, 0.0, 0.0]),
        rocker       = Object3D(),
        rocker_bar   = Object3D(parent = rocker, translation = [0.0, 0.0, -c / 2.0],
                                feature = Solid(shape = Box(lengths = [w, w, c]), solid_material = "Steel")),
        rocker_tip   = Object3D(parent = rocker, translation = [0.0, 0.0, -c],
                                feature = Solid(shape = Sphere(diameter = 0.04), solid_material = "Steel",
                                                collision = true)),
        crank_joint   = Revolute(obj1 = world, obj2 = crank, axis = 3,
                                 phi = Var(init = std::f64::consts::PI), w = Var(init = 6.0)),
        // A rough guess of the coupler's direction; the build closes the loop.
        coupler_joint = Spherical(obj1 = crank_tip, obj2 = coupler, rot = Var(init = [0.0, -0.3, -2.9])),
        // The wall is part of the world, which this joint holds: let them collide.
        rocker_joint  = Revolute(obj1 = rocker_pivot, obj2 = rocker, axis = 1, phi = Var(init = 0.4),
                                 can_collide = true),
        close         = Spherical(obj1 = coupler_tip, obj2 = rocker_tip, cut = true),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = Rssr::default().build()?;
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
