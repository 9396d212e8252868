//! Raw instrument streams reduced to what the identification reads, checked against streams
//! simulated from known readings:
//! - a raw ballbar capture (feed-in, overshoot arc with acceleration, capture arc, overshoot arc
//!   with deceleration, feed-out, sampled at a fixed rate): the capture arc's angles and readings
//!   recovered, the ISO 230-4 values equal to those of the true trace (Jiang 2014 §4.2);
//! - a 1000 Hz 3D-ball stream with a move, a settling oscillation and a dwell at each of the 807
//!   poses of the KX8-Five campaign: the steady value of each pose equal to its reading within the
//!   averaging of the sensor noise (Andolfatto et al. 2011 §3.4).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::iso230_4::circular_values;
use trueaxis::instruments::ballbar::{circle_test, CircleSpec, Plane, Rotation};
use trueaxis::instruments::{capture_arc, steady_values, ArcProgramme, SteadySettings};
use trueaxis::machine::Machine;

/// Polar angle (deg, from the start of the first overshoot) of the ball at time `t` (s) on an arc of
/// `total_deg` run at `speed_deg_s` with constant acceleration over `ramp_deg` at each end.
fn trapezoidal_angle(t: f64, total_deg: f64, speed_deg_s: f64, ramp_deg: f64) -> Option<f64> {
    let accel = speed_deg_s * speed_deg_s / (2.0 * ramp_deg);
    let t_ramp = speed_deg_s / accel;
    let t_cruise = (total_deg - 2.0 * ramp_deg) / speed_deg_s;
    if t < 0.0 || t > 2.0 * t_ramp + t_cruise {
        return None;
    }
    Some(if t < t_ramp {
        0.5 * accel * t * t
    } else if t < t_ramp + t_cruise {
        ramp_deg + speed_deg_s * (t - t_ramp)
    } else {
        let u = 2.0 * t_ramp + t_cruise - t;
        total_deg - 0.5 * accel * u * u
    })
}

#[test]
fn raw_ballbar_capture_gives_the_trace_of_its_capture_arc() {
    // vmc3 with its example errors (squareness, straightness, scale), a 100 mm XY circle run
    // counter-clockwise at 1000 mm/min, 45 deg overshoot, sampled at 250 Hz like a QC20
    let machine = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
    let (radius, feed, rate, overshoot, capture) = (100.0, 1000.0, 250.0, 45.0, 360.0);
    let speed_deg_s = feed / 60.0 / radius * 180.0 / std::f64::consts::PI;
    let total = capture + 2.0 * overshoot;
    let true_angles: Vec<f64> = (0..)
        .map(|k| trapezoidal_angle(k as f64 / rate, total, speed_deg_s, 0.6 * overshoot))
        .take_while(Option::is_some)
        .map(|a| a.unwrap() - overshoot) // 0 at the start of the capture arc
        .collect();
    let spec = CircleSpec {
        plane: Plane::Xy,
        centre: vec![0.0, 0.0, -200.0],
        radius,
        angles: true_angles.iter().map(|a| a.to_radians()).collect(),
        rotation: Rotation::Ccw,
    };
    let test = circle_test(&machine, &spec).unwrap();
    let dl_um: Vec<f64> = test.simulate(&machine, &errors).iter().map(|d| 1e3 * d).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let noise = Normal::new(0.0, 0.1).unwrap();
    // feed-in 1.5 mm -> 0 in 40 samples and feed-out 0 -> 1.5 mm in 37: a few of their samples fall
    // within the 300 um threshold, unequally at the two ends
    let mut stream: Vec<f64> = (0..40).map(|i| 1500.0 * (1.0 - (i + 1) as f64 / 40.0)).collect();
    let arc_start = stream.len();
    stream.extend(dl_um.iter().map(|d| d + noise.sample(&mut rng)));
    stream.extend((0..37).map(|i| 1500.0 * (i + 1) as f64 / 37.0));
    let mut programme = ArcProgramme::new(capture, overshoot);
    (programme.radius_mm, programme.feed_mm_min, programme.sample_rate_hz) = (Some(radius), Some(feed), Some(rate));
    let arc = capture_arc(&stream, &programme).unwrap();
    assert!(arc.warnings.is_empty(), "{:?}", arc.warnings);
    // the samples per degree of the programmed feed; the stretch is longer (acceleration)
    assert!((arc.samples_per_deg - rate / speed_deg_s).abs() < 1e-9);
    assert!(arc.samples_per_deg_of_stretch > arc.samples_per_deg);
    // every capture sample's angle within three sample spacings of its true angle: the feed moves
    // cross the threshold at unequal sample counts (9 and 7 here), which shifts the centre
    let spacing = 1.0 / arc.samples_per_deg;
    let mut worst = 0.0f64;
    for (i, a) in arc.angles_deg.iter().enumerate() {
        worst = worst.max((a - true_angles[arc.first_sample - arc_start + i]).abs());
    }
    eprintln!(
        "{} capture samples, worst angle error {worst:.4} deg (spacing {spacing:.4} deg); first {} vs {}, last {} vs {}, stretch {:?}",
        arc.angles_deg.len(),
        arc.angles_deg[0],
        true_angles[arc.first_sample - arc_start],
        arc.angles_deg.last().unwrap(),
        true_angles[arc.first_sample - arc_start + arc.angles_deg.len() - 1],
        arc.stretch
    );
    assert!(worst < 3.0 * spacing, "worst angle error {worst} deg");
    assert!(arc.angles_deg[0] == 0.0 && (arc.angles_deg.last().unwrap() - 360.0).abs() < 1e-9);
    // the ISO 230-4 values of the recovered trace equal those of the same readings at their true
    // angles
    let truth: Vec<usize> = (0..true_angles.len()).filter(|&k| (0.0..=360.0).contains(&true_angles[k])).collect();
    let rad = |a: &[f64]| a.iter().map(|d| d.to_radians()).collect::<Vec<_>>();
    let mm = |d: &[f64]| d.iter().map(|v| 1e-3 * v).collect::<Vec<_>>();
    let ours = circular_values(Rotation::Ccw, &rad(&arc.angles_deg), &mm(&arc.dev_um), radius).unwrap();
    let t_angles: Vec<f64> = truth.iter().map(|&k| true_angles[k]).collect();
    let t_dl: Vec<f64> = truth.iter().map(|&k| stream[arc_start + k]).collect();
    let exact = circular_values(Rotation::Ccw, &rad(&t_angles), &mm(&t_dl), radius).unwrap();
    eprintln!("G {:.3} vs {:.3} um, centre {:?} vs {:?}", ours.g_um, exact.g_um, ours.centre_um, exact.centre_um);
    assert!(exact.g_um > 2.0, "the errors of vmc3 show on the circle");
    assert!((ours.g_um - exact.g_um).abs() < 0.05, "G {} vs {}", ours.g_um, exact.g_um);
    for k in 0..2 {
        assert!((ours.centre_um[k] - exact.centre_um[k]).abs() < 0.05, "centre {:?} vs {:?}", ours.centre_um, exact.centre_um);
    }
    assert!((ours.radius_change_um - exact.radius_change_um).abs() < 0.02);
}

#[test]
fn raw_ballbar_streams_that_cannot_be_read_are_refused() {
    let programme = ArcProgramme::new(360.0, 45.0);
    // a stream in mm: no feed move, warned
    let mm: Vec<f64> = (0..1000).map(|i| 1e-3 * (i as f64 * 0.01).sin()).collect();
    let arc = capture_arc(&mm, &programme).unwrap();
    assert!(arc.warnings[0].contains("are the samples in um?"), "{:?}", arc.warnings);
    // a stream whose arc is too short for the programmed feed
    let mut p = programme.clone();
    (p.radius_mm, p.feed_mm_min, p.sample_rate_hz) = (Some(150.0), Some(500.0), Some(1000.0));
    let err = capture_arc(&[0.0; 2000], &p).unwrap_err().to_string();
    assert!(err.contains("fewer than") && err.contains("check the feed"), "{err}");
    // a stream twice as long as one run: warned
    let mut p = programme;
    (p.radius_mm, p.feed_mm_min, p.sample_rate_hz) = (Some(100.0), Some(1000.0), Some(100.0));
    let per_run = (p.samples_per_deg().unwrap() * 450.0) as usize;
    let arc = capture_arc(&vec![0.0; 2 * per_run], &p).unwrap();
    assert!(arc.warnings.iter().any(|w| w.contains("more than one run")), "{:?}", arc.warnings);
}

#[test]
fn steady_values_of_a_1000_hz_stream_are_the_readings_of_its_poses() {
    // the 807 readings of the shipped KX8-Five CapBall campaign as dwell values
    let text = std::fs::read_to_string("../../examples/campaigns/kx8five/capball.csv").unwrap();
    let readings: Vec<[f64; 3]> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            [f[5], f[6], f[7]]
        })
        .collect();
    assert_eq!(readings.len(), 807);
    // per pose: a 0.25 s move (cosine blend from the previous reading plus a 25 Hz oscillation of
    // 3 um that decays with 40 ms), then a 0.45 s dwell; noise of Andolfatto et al. 2011 Table 3; 1000 Hz
    let rate = 1000.0;
    let sigma = [0.28, 0.28, 0.40];
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let normal = Normal::new(0.0, 1.0).unwrap();
    let mut channels: [Vec<f64>; 3] = Default::default();
    let mut previous = [0.0; 3];
    for r in &readings {
        for i in 0..700 {
            let t = i as f64 / rate;
            for c in 0..3 {
                let blend = if t < 0.25 { 0.5 - 0.5 * (std::f64::consts::PI * t / 0.25).cos() } else { 1.0 };
                let ring =
                    if t < 0.25 { 0.0 } else { 3.0 * (-(t - 0.25) / 0.04).exp() * (2.0 * std::f64::consts::PI * 25.0 * (t - 0.25)).sin() };
                let moving = if t < 0.25 { 4.0 * (std::f64::consts::PI * t / 0.25).sin() } else { 0.0 }; // dynamic error during the move
                channels[c].push(previous[c] + (r[c] - previous[c]) * blend + ring + moving + sigma[c] * normal.sample(&mut rng));
            }
        }
        previous = *r;
    }
    let settings = SteadySettings::for_stream(rate, 0.40);
    let views: Vec<&[f64]> = channels.iter().map(|c| c.as_slice()).collect();
    let found = steady_values(&views, &settings, readings.len()).unwrap();
    let mut worst = [0.0f64; 3];
    for (p, r) in found.iter().zip(&readings) {
        for c in 0..3 {
            worst[c] = worst[c].max((p.mean[c] - r[c]).abs());
        }
    }
    // each mean averages a few hundred samples: sigma / sqrt(n) is 0.02 um or less; the tail of
    // the settling adds a bias below 0.05 um
    let shortest = found.iter().map(|p| p.end - p.start - 2 * settings.trim).min().unwrap();
    eprintln!("worst steady-value error {worst:?} um, shortest dwell {shortest} samples");
    assert!(shortest >= 250, "{shortest}");
    for c in 0..3 {
        assert!(worst[c] < 0.1 + 4.5 * sigma[c] / (shortest as f64).sqrt(), "channel {c}: {}", worst[c]);
    }
    // a pose missing from the recording is named as a count mismatch with advice
    let err = steady_values(&views, &settings, 808).unwrap_err().to_string();
    assert!(err.contains("807 steady stretches found for 808 poses"), "{err}");
}
