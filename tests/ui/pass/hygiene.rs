//! The expansion is hygienic: user items named like constructors, keys, components and the
//! macro's own locals do not disturb it, and no prelude import is needed.
#![deny(warnings, missing_docs)]

#[allow(dead_code)]
struct Sphere;
#[allow(dead_code)]
struct Scene;
#[allow(dead_code, non_camel_case_types)]
struct world;
#[allow(dead_code)]
fn scene() {}
#[allow(dead_code, non_upper_case_globals)]
const parent: u8 = 0;
#[allow(dead_code, non_upper_case_globals)]
const object: u8 = 0;
#[allow(dead_code)]
mod core {}
#[allow(dead_code)]
mod std {}

modia3d::model! {
    /// A sub-assembly whose parameters are named like the macro's locals.
    pub assembly Part(scene: f64 = 0.1, prefix: f64 = 1.0, size: f64 = 0.5) {
        body = Object3D(feature = Solid(shape = Sphere(diameter = scene), solid_material = "Steel")),
        tip = Object3D(parent = body, translation = [0.0, 0.0, prefix * size]),
    }
}

modia3d::model! {
    /// A model using it.
    pub Top(length: f64 = 2.0) {
        world = Object3D(feature = Scene()),
        part = Part(prefix = length),
        rev = Revolute(obj1 = world, obj2 = part.tip),
    }
}

fn main() {
    let s = Top::default().scene();
    assert_eq!(s.objects[2].name, "part.tip");
    assert_eq!(s.objects[2].translation[2], 1.0);
    let _ = Top::default().build().unwrap();
}
