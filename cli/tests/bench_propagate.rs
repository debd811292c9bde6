//! `satflock bench propagate`: its JSON line, its final states against `satflock propagate`'s RK4 (the
//! generic stepper, an independent path), and its refusals.

mod common;

use common::{satflock, scratch_dir, stderr};

/// Runs the command and returns its JSON line.
fn bench_json(args: &[&str]) -> serde_json::Value {
    let out = satflock()
        .args(["bench", "propagate"])
        .args(args)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().count(), 1, "{text}");
    serde_json::from_str(text.trim()).unwrap()
}

#[test]
fn json_line_and_final_state_equal_the_generic_rk4_of_satflock_propagate() {
    let dir = scratch_dir("bench-propagate");
    let initial = dir.join("initial.csv");
    std::fs::write(
        &initial,
        "sat,x,y,z,vx,vy,vz\n\
         7,6878137.0,1000.5,-2000.25,-1.5,4500.0,6143.0\n\
         9,-5000000.0,4000000.0,2500000.0,-4400.0,-6050.0,880.0\n\
         11,0.0,7000000.0,0.0,-7546.0,0.0,0.0\n",
    )
    .unwrap();
    let finals = dir.join("final.csv");
    for threads in ["1", "2"] {
        let json = bench_json(&[
            "--initial-states",
            initial.to_str().unwrap(),
            "--duration-s",
            "100.5",
            "--step-s",
            "2",
            "--threads",
            threads,
            "--write-final",
            finals.to_str().unwrap(),
        ]);
        for key in [
            "peer",
            "n",
            "steps",
            "wall_s",
            "sat_steps_per_s",
            "threads",
            "final_state_first_sat",
        ] {
            assert!(json.get(key).is_some(), "{key} missing in {json}");
        }
        assert_eq!(json["peer"], "satflock");
        assert_eq!(json["n"], 3);
        assert_eq!(json["steps"], 51);
        assert_eq!(json["threads"], threads.parse::<u64>().unwrap());
        assert!(json["sat_steps_per_s"].as_f64().unwrap() > 0.0);
        let first: Vec<f64> = json["final_state_first_sat"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        // Every satellite against `satflock propagate --integrator rk4` alone.
        let text = std::fs::read_to_string(&finals).unwrap();
        let mut rows = text.lines();
        assert_eq!(rows.next(), Some("sat,x,y,z,vx,vy,vz"));
        let initial_text = std::fs::read_to_string(&initial).unwrap();
        for (row, start) in rows.zip(initial_text.lines().skip(1)) {
            let (id, state) = start.split_once(',').unwrap();
            let out = dir.join(format!("orbit-{id}.csv"));
            let o = satflock()
                .args(["propagate", "--state", state, "--duration-s", "100.5"])
                .args([
                    "--output-step-s",
                    "100.5",
                    "--integrator",
                    "rk4",
                    "--step-s",
                    "2",
                ])
                .args(["--gravity", "j2", "--out", out.to_str().unwrap()])
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", stderr(&o));
            let orbit = std::fs::read_to_string(&out).unwrap();
            let last: Vec<f64> = orbit
                .lines()
                .last()
                .unwrap()
                .split(',')
                .skip(1)
                .map(|v| v.parse().unwrap())
                .collect();
            let got: Vec<f64> = row.split(',').skip(1).map(|v| v.parse().unwrap()).collect();
            assert_eq!(row.split(',').next(), Some(id));
            assert_eq!(got, last, "satellite {id}");
            if id == "7" {
                assert_eq!(first, last);
            }
        }
    }
}

#[test]
fn generated_states_are_deterministic_and_independent_of_threads() {
    let run = |threads: &str| {
        bench_json(&["--n", "1030", "--duration-s", "20", "--threads", threads])
            ["final_state_first_sat"]
            .clone()
    };
    let one = run("1");
    assert_eq!(one, run("2"));
    let r: f64 = one.as_array().unwrap()[..3]
        .iter()
        .map(|v| v.as_f64().unwrap().powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((6.7e6..7.7e6).contains(&r), "{r}");
}

#[test]
fn bad_options_exit_2_naming_the_option_and_range() {
    let dir = scratch_dir("bench-refusals");
    let wrong = dir.join("wrong.csv");
    std::fs::write(&wrong, "id,x,y,z,vx,vy,vz\n0,7e6,0,0,0,7.5e3,0\n").unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["--n", "0", "--duration-s", "10"], "--n"),
        (&["--n", "10", "--duration-s", "-1"], "--duration-s"),
        (
            &["--n", "10", "--duration-s", "10", "--step-s", "0"],
            "--step-s",
        ),
        (&["--duration-s", "10"], "--n"),
        (
            &["--n", "10", "--duration-s", "10", "--threads", "0"],
            "--threads",
        ),
        (
            &[
                "--initial-states",
                wrong.to_str().unwrap(),
                "--duration-s",
                "10",
            ],
            "sat,x,y,z,vx,vy,vz",
        ),
    ];
    for (args, named) in cases {
        let out = satflock()
            .args(["bench", "propagate"])
            .args(args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(named), "{args:?}: {}", stderr(&out));
    }
}
