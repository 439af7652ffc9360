//! Colliding solids whose contact materials have no pair entry, where the macro must not
//! report one: they cannot meet (one rigid body; a Fix; a Revolute or Prismatic without
//! `can_collide`), or the macro cannot know (a non-literal material or `can_collide`, a
//! sub-assembly, contact detection off, a pair entry with a non-literal name), or the block
//! defines the pair.
#![deny(warnings)]

use modia3d::prelude::*;

model! {
    /// Steel and DryWood on one rigid body (a parent link).
    pub Rigid {
        world = Object3D(feature = Scene()),
        a = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel", collision = true)),
        b = Object3D(parent = a, translation = [0.2, 0.0, 0.0],
                     feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "DryWood", collision = true)),
        free = FreeMotion(obj1 = world, obj2 = a),
    }
}

model! {
    /// Steel and Aluminium joined by a Fix (one body); Steel and DryWood joined by a Revolute
    /// without `can_collide`; DryWood and BilliardTable by a Prismatic whose `can_collide` is
    /// known at run time only.
    pub Joined(on: bool = false) {
        world = Object3D(feature = Scene()),
        a = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel", collision = true)),
        c = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Aluminium", collision = true)),
        d = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "DryWood", collision = true)),
        e = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), contact_material = "BilliardTable", mass_properties = MassProperties(mass = 1.0),
                                     collision = true)),
        free = FreeMotion(obj1 = world, obj2 = a),
        fix = Fix(obj1 = a, obj2 = c),
        rev = Revolute(obj1 = a, obj2 = d),
        slide = Prismatic(obj1 = d, obj2 = e, can_collide = on),
        wood_table = ContactPair(material1 = "DryWood", material2 = "BilliardTable", cor = 0.5, mu_k = 0.3, mu_r = 0.0),
        a_table = ContactPair(material1 = "Steel", material2 = "BilliardTable", cor = 0.5, mu_k = 0.3, mu_r = 0.0),
        al_table = ContactPair(material1 = "Aluminium", material2 = "BilliardTable", cor = 0.5, mu_k = 0.3, mu_r = 0.0),
    }
}

model! {
    /// A material and a `collision` known at run time only; a pair defined in the block.
    pub NonLiteral(name: &'static str = "Aluminium", on: bool = true) {
        world = Object3D(feature = Scene()),
        top = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "DryWood",
                                                       collision = true)),
        f = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = name, collision = true)),
        g = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Aluminium", collision = on)),
        h = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel", collision = true)),
        free_f = FreeMotion(obj1 = world, obj2 = f),
        free_g = FreeMotion(obj1 = world, obj2 = g),
        free_h = FreeMotion(obj1 = world, obj2 = h),
        steel_wood = ContactPair(material1 = "DryWood", material2 = "Steel", cor = 0.5, mu_k = 0.3, mu_r = 0.001),
    }
}

model! {
    /// Contact detection off.
    pub Off {
        world = Object3D(feature = Scene(contact_detection = false)),
        top = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "Steel",
                                                       collision = true)),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "DryWood", collision = true)),
        free = FreeMotion(obj1 = world, obj2 = ball),
    }
}

model! {
    /// A pair entry with a name known only at run time.
    pub Unsure(other: &'static str = "DryWood") {
        world = Object3D(feature = Scene()),
        top = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "Steel",
                                                       collision = true)),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "DryWood", collision = true)),
        free = FreeMotion(obj1 = world, obj2 = ball),
        pair = ContactPair(material1 = "Steel", material2 = other, cor = 0.5, mu_k = 0.3, mu_r = 0.0),
    }
}

model! {
    /// A ball of its own (the outer model may define its pairs).
    pub assembly Ball {
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "DryWood", collision = true)),
    }
}

model! {
    /// A sub-assembly: it may add pairs, so nothing is reported here.
    pub WithBall {
        world = Object3D(feature = Scene()),
        top = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "Aluminium",
                                                       collision = true)),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel", collision = true)),
        free = FreeMotion(obj1 = world, obj2 = ball),
        other = Ball(),
    }
}

fn main() {
    let _ = (Rigid::default(), Joined::default(), NonLiteral::default());
    let _ = (Off::default(), Unsure::default(), WithBall::default());
}
