//! Item 12: SIGINT, SIGTERM and SIGHUP during the write phase remove the run's temporaries; the
//! old output stays whole and the exit status is 3 (interrupted).

use super::{names, trueaxis, vmc3_in};
use std::io::Write;
use std::process::Stdio;
use std::time::{Duration, Instant};

#[cfg(unix)]
#[test]
fn a_signal_removes_the_temporaries_of_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    vmc3_in(d);
    let out = d.join("table.csv");
    for signal in ["INT", "TERM", "HUP"] {
        std::fs::write(&out, "the old table\n").unwrap();
        let fifo = d.join("poses.fifo");
        let _ = std::fs::remove_file(&fifo);
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        // the poses come through a FIFO that stays open: predict has its temporary and waits for
        // more rows when the signal comes
        let child = trueaxis(&[
            "predict",
            "--machine",
            d.join("m.toml").to_str().unwrap(),
            "--errors",
            d.join("e.toml").to_str().unwrap(),
            "--poses",
            fifo.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
        let mut writer = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
        writer.write_all(b"X,Y,Z\n0,0,0\n-10,-20,-30\n").unwrap();
        writer.flush().unwrap();
        let start = Instant::now();
        while !names(d).iter().any(|n| n.starts_with(".table.csv.trueaxis-")) {
            assert!(start.elapsed() < Duration::from_secs(60), "no temporary appeared: {:?}", names(d));
            std::thread::sleep(Duration::from_millis(5));
        }
        let s = std::process::Command::new("kill").arg(format!("-{signal}")).arg(child.id().to_string()).status().unwrap();
        assert!(s.success());
        let o = child.wait_with_output().unwrap();
        drop(writer);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "SIG{signal}: {err}");
        assert!(err.contains(&format!("interrupted by SIG{signal}")) && err.contains("removed its temporary file"), "{err}");
        assert_eq!(names(d), ["e.toml", "m.toml", "p.csv", "poses.fifo", "table.csv"], "SIG{signal}: a temporary is left");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "the old table\n");
    }
}
