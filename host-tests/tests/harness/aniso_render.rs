//! Anisotropic filtering on the hall (the floor recedes to the horizon):
//! against ground truth it must beat isotropic trilinear filtering at the
//! same ray-differential footprint, in fixed point and in f64, and the
//! fixed-point render must stay close to the f64 one.

use raymip_host::output::metrics::psnr;
use raymip_host::render::{Arithmetic, Method, Options, Prepared, render, render_truth};
use raymip_host::scene::load_scene;

#[test]
fn aniso_beats_trilinear_on_the_hall() {
    let size = (160, 96);
    let prep = Prepared::new(load_scene("builtin:hall", 0.0).unwrap(), Some(size)).unwrap();
    let base = Options {
        method: Method::Raydiff,
        size: Some(size),
        spp: 32,
        ..Options::default()
    };
    let truth = render_truth(&prep, &base).to_rgb8();
    let img = |arithmetic, aniso| {
        render(
            &prep,
            &Options {
                arithmetic,
                aniso,
                ..base.clone()
            },
        )
        .to_rgb8()
    };
    for arithmetic in [Arithmetic::Fixed, Arithmetic::Float] {
        let tri = psnr(&img(arithmetic, None), &truth);
        let an = psnr(&img(arithmetic, Some(16)), &truth);
        eprintln!("{arithmetic:?}: trilinear {tri:.2} dB, aniso 16x {an:.2} dB");
        assert!(
            an > tri + 0.1,
            "{arithmetic:?}: aniso {an} vs trilinear {tri}"
        );
    }
    let fixed = img(Arithmetic::Fixed, Some(16));
    let float = img(Arithmetic::Float, Some(16));
    assert!(
        psnr(&fixed, &float) > 45.0,
        "fixed vs float {}",
        psnr(&fixed, &float)
    );
}
