//! The contact hot path allocates nothing: residual (continuous mode), root functions
//! (zero-crossing mode) and event mode of the billiards scene, once warmed up. A counting
//! global allocator; this binary holds a single test so that nothing else allocates meanwhile.

use modia3d::core::dae::MultibodyDae;
use modia3d::core::solver::DaeSystem;
use modia3d::demo;
#[path = "../modia3d-core/tests/common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocs;
use std::sync::Arc;

#[test]
fn residual_roots_and_events_do_not_allocate() {
    let model = demo::billiards16([3.0, 0.1, 0.0], 1.0).build().unwrap();
    let plan = Arc::new(model.plan().clone());
    let contact = model.contact_plan().map(|c| Arc::new(c.clone()));
    let mut dae = MultibodyDae::new(plan.clone(), contact);
    let y = plan.y0();
    let n = y.len();
    dae.handle_event(0.0, &y).unwrap();
    let yp = dae.consistent_derivative(0.0, &y).unwrap();
    let mut res = vec![0.0; n];
    let mut g = vec![0.0; 2];
    // Warm up.
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    dae.roots(0.0, &y, &yp, &mut g);
    let before = allocs();
    for k in 0..100 {
        let t = k as f64 * 1e-3;
        dae.residual(t, &y, &yp, &mut res).unwrap();
        dae.roots(t, &y, &yp, &mut g);
        dae.handle_event(t, &y).unwrap();
    }
    let after = allocs();
    assert_eq!(after - before, 0, "allocations on the contact hot path");
    assert!(
        g[0] < 0.0 && g[1] > 0.0,
        "balls rest on the table, none touch: {g:?}"
    );
    assert!(res.iter().all(|r| r.abs() < 1e-6), "consistent start");
}
