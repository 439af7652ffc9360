//! Plots of a mixed-unit run: Newton's cradle (five steel balls on pendulums), the first and
//! last pendulum angles [rad] in one subplot and two contact forces [N] in another, with
//! vertical lines at the contact events. Writes the same figure as SVG and as PNG, and a
//! log-scale plot of the forces, to `out/`.

use modia3d::demo;
use modia3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model =
        demo::newtons_cradle(0.05, 1e-3, 0.5, ContactPairMaterial::new(1.0, 0.0, 0.0)).build()?;
    let result = model.simulate(
        &SimOptions::new(1.0)
            .tolerance(1e-7)
            .interval(1e-4)
            .contact_results(true),
    )?;
    std::fs::create_dir_all("out")?;
    let names = ["rev0.phi", "rev4.phi", "ball0|ball1.f_n", "ball3|ball4.f_n"];
    let options = PlotOptions::new().title("Newton's cradle");
    for path in ["out/cradle.svg", "out/cradle.png"] {
        result.plot_with(&names, path, &options)?;
    }
    result.plot_groups(
        &[&["ball0|ball1.f_n", "ball3|ball4.f_n"]],
        "out/cradle_forces_log.png",
        &PlotOptions::new()
            .title("contact forces (log scale)")
            .log_y(true)
            .size(900, 400),
    )?;
    println!(
        "{} contact events; wrote out/cradle.{{svg,png}} and out/cradle_forces_log.png",
        result.events.len()
    );
    Ok(())
}
