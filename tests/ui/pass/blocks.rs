//! Every block kind `model!` takes, inputs as expressions over parameters, `time` and signals,
//! and signals read inside a sub-assembly.
use modia3d::prelude::*;

model! {
    pub assembly Axis(gain: f64 = 1.0) {
        base  = Object3D(),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev   = Revolute(obj1 = base, obj2 = load),
        pi    = PI(k = gain, T = 1.0, u = -rev.w),
        drive = Drive(joint = rev, ratio = 100.0, J_motor = 1e-5, tau = pi.y),
    }
}

model! {
    pub M(k: f64 = 2.0, label: String = String::from("x")) {
        world = Object3D(feature = Scene()),
        c     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        e     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        cyl   = Cylindrical(obj1 = world, obj2 = c),
        slide = Prismatic(obj1 = world, obj2 = e),
        axis  = Axis(parent = world, gain = k),
        k0    = Constant(k = k),
        st    = Step(height = 1, startTime = 0.5),
        ramp  = Ramp(height = 1.0, duration = 2.0, offset = 0.1),
        sine  = Sine(amplitude = 1.0, f = 2.0),
        tab   = Table(table = [(0, 0), (1.0, 2)]),
        inp   = Input(start = 1.0),
        ptp   = PtpPath(positions = [[0.0, 0.0], [1.0, 2.0]], v_max = [1.0, 1.0], a_max = vec![2.0, 2.0]),
        g     = Gain(k = k, u = time),
        fb    = Feedback(u1 = ptp.q1, u2 = ptp.qd2),
        add   = Add(k2 = -1.0, u1 = 1.0, u2 = k * st.y),
        add3  = Add3(u1 = sine.y, u2 = tab.y, u3 = inp.y.max(0.0) + k0.y),
        lim   = Limiter(uMax = 2.0, u = add.y + add3.y),
        int   = Integrator(u = lim.y),
        fo    = FirstOrder(T = 0.1, u = if time < 1.0 { int.y } else { -int.x }),
        pid   = PID(Ti = 0.5, Td = 0.1, u = fo.y),
        lpid  = LimPID(Ti = 0.5, Td = 0.1, yMax = 10.0, u_s = ramp.y, u_m = cyl.s + label.len() as f64),
        drive = Drive(joint = cyl, coordinate = "phi", ratio = 10.0, J_motor = 1e-4, tau = lpid.y + pid.y),
        far   = Gain(k = 1.0, u = axis.drive.motor_w + axis.rev.phi + axis.pi.x),
        dc    = Drive(joint = slide, ratio = 100.0, J_motor = 1e-5, gear = Elastic(c = 10000, d = k),
                      motor = Dc(R = 1.0, L = 1e-3, k = 0.1), v = -dc.i - dc.phi_gear + slide.v),
        dig   = Sampled(period = 0.01, startTime = 0.005, inner = PID(Ti = 1, Td = 0.1), u = ramp.y - dig.xi),
        rigid = Drive(joint = cyl, coordinate = "s", ratio = 1.0, J_motor = 0.0, gear = Rigid, motor = Torque, tau = dc.motor_w),
    }
}

fn main() {
    let scene = M::default().scene();
    assert_eq!(scene.components.len(), 23);
}
