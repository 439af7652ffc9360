use modia3d::prelude::*;

model! {
    pub M(length: f64 = 1.0) {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        tip = Object3D(parent = bdy, translation = [0.0, 0.0, length]),
    }
}

// Only the error in the block is reported: the type and its methods still exist.
fn main() {
    let m = M { length: 2.0 };
    let _ = m.scene();
    let _ = M::default().build();
}
