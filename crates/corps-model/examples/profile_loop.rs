//! Runs one algorithm in a loop on TALOS, for profilers (perf, callgrind):
//! `cargo run --release -p corps-model --example profile_loop -- crba 100000`.

use corps_model::*;

fn main() {
    let mut args = std::env::args().skip(1);
    let algo = args.next().unwrap_or_else(|| "crba".into());
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/talos_data/robots/talos_reduced.urdf"
    );
    let model = build_model_from_urdf_file(path, RootJoint::FreeFlyer).expect("TALOS loads");
    let mut data = Data::new(&model);
    let mut rng = rand::thread_rng();
    let q = random_configuration(&model, &mut rng);
    let v = vec![0.3; model.nv];
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        let r = match algo.as_str() {
            "crba" => crba(&model, &mut data, q.as_slice()).map(|_| ()),
            "rnea" => rnea(&model, &mut data, q.as_slice(), &v, &v).map(|_| ()),
            "aba" => aba(&model, &mut data, q.as_slice(), &v, &v).map(|_| ()),
            "jac" => compute_joint_jacobians(&model, &mut data, q.as_slice()).map(|_| ()),
            "ccrba" => compute_centroidal_momentum(&model, &mut data, q.as_slice(), &v).map(|_| ()),
            "all" => compute_all_terms(&model, &mut data, q.as_slice(), &v),
            "minv" => compute_minverse(&model, &mut data, q.as_slice()).map(|_| ()),
            other => {
                eprintln!("unknown algorithm {other}");
                std::process::exit(2);
            }
        };
        std::hint::black_box(r).expect("valid state");
        std::hint::black_box(&mut data);
    }
    eprintln!(
        "{algo}: {:.3} us/call",
        t0.elapsed().as_secs_f64() * 1e6 / n as f64
    );
}
