//! `trueaxis uncertainty --machine M --campaign C.toml` (the docs/design.md, Command line form): the design is
//! the campaign's identification. Checked against `trueaxis identify` on the same campaign: with
//! only the stated sensor noise as a source, the GUM standard uncertainty of each parameter is the
//! identification's least-squares one without the s0 scaling, `u_identify = s0 u_GUM` (Soons 1993
//! eq. 4.11 with Cov = s0^2 (X^T W X)^-1), to 1e-6 relative; and the estimates are the identified
//! values.

use crate::support::json_of;

#[test]
fn campaign_form_agrees_with_identify() {
    let dir = tempfile::tempdir().unwrap();
    let sources = dir.path().join("noise.toml");
    std::fs::write(
        &sources,
        "coverage = 0.95\ntolerance = 0.05\nseed = 3\n[[source]]\nname = \"sensors\"\nkind = \"noise\"\n\
         channels.x = { distribution = \"normal\", u = 0.28 }\nchannels.y = { distribution = \"normal\", u = 0.28 }\n\
         channels.z = { distribution = \"normal\", u = 0.40 }\n",
    )
    .unwrap();
    let (m, c) = ("examples/machines/kx8five.toml", "examples/campaigns/kx8five/campaign.toml");
    let u = json_of(&["uncertainty", "--machine", m, "--campaign", c, "--sources", sources.to_str().unwrap(), "--json"]);
    let id = json_of(&["identify", "--machine", m, "--campaign", c, "--json"]);
    let s0 = id["sigma0"].as_f64().unwrap();
    let names = u["parameter_order"].as_array().unwrap();
    assert_eq!(names.len(), 12);
    for name in names {
        let name = name.as_str().unwrap();
        let p = &u["parameters"][name];
        let (gum_u, gum_mean) = (p["gum"]["std_uncertainty"].as_f64().unwrap(), p["gum"]["estimate"].as_f64().unwrap());
        let (id_u, id_value) =
            (id["parameters"][name]["std_uncertainty"].as_f64().unwrap(), id["parameters"][name]["value"].as_f64().unwrap());
        assert!((id_u - s0 * gum_u).abs() <= 1e-6 * id_u, "{name}: identify u {id_u} vs s0 * GUM u {}", s0 * gum_u);
        assert!((gum_mean - id_value).abs() <= 1e-6 * (1.0 + id_value.abs()), "{name}: estimate {gum_mean} vs {id_value}");
        // and the Monte Carlo agrees with GUM on this linear Gaussian model within the tolerance
        let mc_u = p["std_uncertainty"].as_f64().unwrap();
        assert!((mc_u - gum_u).abs() < 0.05, "{name}: MC u {mc_u} vs GUM {gum_u}");
    }
}
