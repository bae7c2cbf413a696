//! Points on an imported model by position (spec §15): `at = [x, y, z]` is the node there
//! (the same power as naming it), within a tolerance and never farther; a frame's legs
//! follow its stack's node along `direction`; and studies over nodes — a box of the model's
//! nodes swept and optimised — agree with each other.

use beamflow::analysis::budget::Budget;
use beamflow::optimize::{self, RunOptions, Spec};
use beamflow::sweep::{self, Sweep};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The paper beam on a uniform 0.01 m mesh, exported by beamflow and imported back: the
/// folder, the `[imported]` table and the exported nodes' (id, x) with a `w` row.
struct Model {
    dir: tempfile::TempDir,
    table: String,
    nodes: Vec<(i64, f64)>,
}

fn model() -> Model {
    let dir = tempfile::tempdir().unwrap();
    let native = dir.path().join("native.toml");
    std::fs::write(
        &native,
        "[beam]\nlength = 0.73\n[beam.mesh]\nelements = 73\n[[actuator]]\ntype = \"inertial\"\nx_e = 0.15\n\
         [actuator.voltage]\nkind = \"sine\"\namplitude = 1.0\nfrequency = 60.0\n[output]\nmatrices = true\nplots = false\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    beamflow::app::commands::run(&native, Some(&out), None, false, false, &Budget::default()).unwrap();
    let p = |n: &str| out.join(format!("native_structure_{n}")).display().to_string();
    let table = format!(
        "[imported]\nmass = {:?}\nstiffness = {:?}\ndofs = {:?}\n[damping]\nkind = \"rayleigh\"\na0 = 5.0\na1 = 1e-5\n",
        p("M.mtx"),
        p("K.mtx"),
        p("dofs.csv")
    );
    let text = std::fs::read_to_string(p("dofs.csv")).unwrap();
    let mut nodes: Vec<(i64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[5] == "w")
        .map(|f| (f[1].parse().unwrap(), f[2].parse().unwrap()))
        .collect();
    nodes.sort_by(|a, b| a.1.total_cmp(&b.1));
    assert!(nodes.len() > 60, "{} nodes", nodes.len());
    Model { dir, table, nodes }
}

impl Model {
    /// The node nearest x and its position.
    fn node(&self, x: f64) -> (i64, f64) {
        *self.nodes.iter().min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs())).unwrap()
    }

    /// A case of one actuator written as `actuator` (its type and point), driven at 1 V.
    fn case(&self, name: &str, actuator: &str) -> PathBuf {
        let p = self.dir.path().join(format!("{name}.toml"));
        std::fs::write(
            &p,
            format!(
                "{}[[actuator]]\n{actuator}\n[actuator.stack]\nhysteresis = false\n[actuator.voltage]\nkind = \"sine\"\n\
                 amplitude = 1.0\nfrequency = 60.0\n[[analysis]]\ntype = \"steady_state\"\nharmonics = 1\n\
                 [output]\nplots = false\nhdf5 = false\n",
                self.table
            ),
        )
        .unwrap();
        p
    }

    fn run(&self, case: &Path) -> Result<Value, String> {
        let out = self.dir.path().join("runs");
        beamflow::app::commands::run(case, Some(&out), None, false, false, &Budget::default())
            .map_err(|e| e.to_string())?;
        let stem = case.file_stem().unwrap().to_str().unwrap();
        Ok(serde_json::from_str(&std::fs::read_to_string(out.join(format!("{stem}.json"))).unwrap()).unwrap())
    }

    fn power(&self, name: &str, actuator: &str) -> Result<Value, String> {
        let p = self.case(name, actuator);
        self.run(&p).map(|v| v["analyses"][0]["mean_power_w"].clone())
    }
}

#[test]
fn a_position_is_the_node_there_within_the_tolerance_and_refused_beyond_it() {
    let m = model();
    let (id, x) = m.node(0.3);
    let inertial = "type = \"inertial\"\nname = \"shaker\"\ncomponent = \"w\"";
    let named = m.power("named", &format!("{inertial}\nnode = {id}")).unwrap();
    assert!(named["shaker_stack"].as_f64().unwrap() > 0.0, "{named}");
    // At the node, and off it by less than 1 % of the 0.01 m spacing: the node's power.
    for (dx, tolerance) in [(0.0, ""), (3e-5, ""), (0.004, "\ntolerance = 0.005")] {
        let at = m.power("at", &format!("{inertial}\nat = [{}, 0.0, 0.0]{tolerance}", x + dx)).unwrap();
        assert_eq!(at, named, "at x = {} m", x + dx);
    }
    // Farther than the tolerance, or midway between two nodes: refused, naming the field
    // and the nearest node, before anything is solved.
    let (next, x1) = m.node(x + 0.01);
    for (point, expect) in [
        (format!("at = [{}, 0.0, 0.0]", x + 0.004), format!("the nearest is node {id}")),
        (format!("at = [{}, 0.0, 0.0]\ntolerance = 0.001", x + 0.004), format!("node = {id}")),
        (format!("at = [{}, 0.0, 0.0]\ntolerance = 0.02", 0.5 * (x + x1)), format!("nodes {id} and {next}")),
        (format!("at = [{}, 0.0, 0.2]", x), "0.2 m away".to_string()),
    ] {
        let e = m.power("far", &format!("{inertial}\n{point}")).unwrap_err();
        assert!(e.contains("far.toml") && e.contains("actuator[0].at") && e.contains(&expect), "{e} ({expect})");
    }
    // Malformed: the field and what to write.
    for (point, field, expect) in [
        (format!("at = [{x}, 0.0]"), "actuator[0].at", "[x, y, z]"),
        (format!("node = {id}\ntolerance = 0.001"), "actuator[0].tolerance", "goes with"),
        (format!("at = [{x}, 0.0, 0.0]\ntolerance = -1.0"), "actuator[0].tolerance", "zero or positive"),
        (format!("at = [{x}, 0.0, nan]"), "actuator[0].at", "not a finite number"),
    ] {
        let e = m.power("bad", &format!("{inertial}\n{point}")).unwrap_err();
        assert!(e.contains("bad.toml") && e.contains(field) && e.contains(expect), "{e} ({field}: {expect})");
    }
    // A sensor by position reads the node's motion; off the model it is refused by name.
    let sensor = |at: f64| {
        let p = m.case("sensed", &format!("{inertial}\nnode = {id}"));
        let text = std::fs::read_to_string(&p).unwrap();
        std::fs::write(&p, format!("{text}[[sensor]]\nname = \"s\"\nat = [{at}, 0.0, 0.0]\ncomponent = \"w\"\n"))
            .unwrap();
        m.run(&p)
    };
    assert!(sensor(x).is_ok());
    let e = sensor(x + 0.005).unwrap_err();
    assert!(e.contains("sensor[0].at") && e.contains("the nearest is node"), "{e}");
}

#[test]
fn a_frames_legs_follow_its_stack_node_along_its_direction() {
    let m = model();
    let (s, x) = m.node(0.3);
    let (l, r) = (m.node(x - 0.02).0, m.node(x + 0.02).0);
    let frame = "type = \"frame\"\nname = \"frame\"\ncomponent = \"w\"\na = 0.02\ne = 0.0";
    let named = m.power("legs", &format!("{frame}\nnode = {s}\nlegs = [{l}, {r}]")).unwrap();
    assert_eq!(named.as_object().map(|o| o.len()), Some(3), "{named}");
    assert_eq!(m.power("follow", &format!("{frame}\nnode = {s}")).unwrap(), named);
    assert_eq!(m.power("by_position", &format!("{frame}\nat = [{x}, 0.0, 0.0]")).unwrap(), named);
    // Turned half a turn the legs swap sides: the same stack power.
    let turned = m.power("turned", &format!("{frame}\nnode = {s}\ndirection = 180.0")).unwrap();
    assert_eq!(turned["frame_stack"], named["frame_stack"]);
    // A leg with no node under it (off the end, or between nodes) is refused by name.
    let (end, _) = m.node(0.72);
    let e = m.power("off", &format!("{frame}\nnode = {end}")).unwrap_err();
    assert!(e.contains("actuator[0].direction") && e.contains("right leg") && e.contains("nearest is node"), "{e}");
    let e = m.power("between", &format!("{frame}\nnode = {s}").replace("a = 0.02", "a = 0.015")).unwrap_err();
    assert!(e.contains("actuator[0].direction") && e.contains("left leg"), "{e}");
}

const BOX: &str = "nodes_in = { min = [0.0, -1.0, -1.0], max = [0.73, 1.0, 1.0] }";

#[test]
fn an_optimum_over_a_box_of_nodes_is_the_best_of_the_same_nodes_swept() {
    let m = model();
    let base = m
        .case("base", "type = \"frame\"\nname = \"frame\"\ncomponent = \"w\"\na = 0.02\ne = 0.0\nat = [0.3, 0.0, 0.0]");
    let text = std::fs::read_to_string(&base).unwrap().replace("frequency = 60.0", "frequency = 300.0");
    std::fs::write(&base, text).unwrap();
    let sweep_text =
        format!("base = \"base.toml\"\nharmonics = 1\n[[parameter]]\npath = \"actuator[0].node\"\n{BOX}\n");
    let sw = Sweep::from_str(&sweep_text, "nodes.sweep.toml", m.dir.path()).unwrap();
    // Every node the frame fits on: its legs 0.02 m either side on nodes with a w row (the
    // clamped ends have none), so the two nodes next to each end are left out.
    let xs: Vec<f64> =
        sw.parameters[0].values.iter().map(|&id| m.nodes.iter().find(|n| n.0 == id as i64).unwrap().1).collect();
    assert_eq!(xs.len(), m.nodes.len() - 4, "{xs:?}");
    assert!(xs.iter().all(|&x| (0.03 - 1e-12..=0.70 + 1e-12).contains(&x)), "{xs:?}");
    let t = sweep::run(&sw, &sweep::RunOptions { threads: Some(2), ..Default::default() }).unwrap();
    let best = t.rows.iter().max_by(|a, b| a.net_power[0].total_cmp(&b.net_power[0])).unwrap();
    let opt = format!(
        "base = \"base.toml\"\nharmonics = 1\n[search]\nseed = 3\nstarts = 4\nevaluations = 400\ntop = 1\n\
         [[variable]]\npath = \"actuator[0].node\"\n{BOX}\n[[objective]]\nquantity = \"net_power\"\n"
    );
    let s = Spec::from_str(&opt, "nodes.opt.toml", m.dir.path()).unwrap();
    let r = optimize::run(&s, &RunOptions { threads: Some(2), ..Default::default() }).unwrap();
    let node = s.variables[0].value(r.best.u[0]);
    eprintln!(
        "sweep: {:e} W at node {}; optimiser: {:e} W at node {node}",
        best.net_power[0], best.inputs[0], r.best.values[0]
    );
    assert!((r.best.values[0] - best.net_power[0]).abs() <= 1e-9 * best.net_power[0]);
    let swept = t.rows.iter().find(|row| row.inputs[0] == node.as_integer().unwrap() as f64).unwrap();
    assert_eq!(swept.net_power[0], r.best.values[0], "the optimiser's node swept");
}

#[test]
fn a_box_of_nodes_is_refused_when_it_holds_none_or_names_no_node_field() {
    let m = model();
    m.case("base", "type = \"inertial\"\ncomponent = \"w\"\nnode = 1");
    let base_node = m.node(0.3).0;
    let base = m.dir.path().join("base.toml");
    let text = std::fs::read_to_string(&base).unwrap().replace("node = 1\n", &format!("node = {base_node}\n"));
    std::fs::write(&base, text).unwrap();
    for (path, nodes_in, field, expect) in [
        (
            "actuator[0].node",
            "{ min = [0.8, 0.0, 0.0], max = [0.9, 0.0, 0.0] }",
            "parameter[0].nodes_in",
            "no node with a free w DOF",
        ),
        ("actuator[0].node", "{ min = [0.5, 0.0, 0.0], max = [0.4, 0.0, 0.0] }", "parameter[0].nodes_in.max", "below"),
        (
            "actuator[0].x_e",
            "{ min = [0.0, 0.0, 0.0], max = [0.7, 0.0, 0.0] }",
            "parameter[0].nodes_in",
            "vary a `node` field",
        ),
        (
            "actuator[0].node",
            "{ min = [0.0, 0.0, 0.0], max = [0.7, 0.0, 0.0], component = \"uz\" }",
            "parameter[0].nodes_in",
            "no node with a free uz DOF",
        ),
    ] {
        let text = format!("base = \"base.toml\"\n[[parameter]]\npath = \"{path}\"\nnodes_in = {nodes_in}\n");
        let e = Sweep::from_str(&text, "box.sweep.toml", m.dir.path()).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains("box.sweep.toml") && e.contains(field) && e.contains(expect), "{e} ({field}: {expect})");
    }
    let text = format!("base = \"base.toml\"\n[[variable]]\npath = \"actuator[0].node\"\nvalues = [1]\n{BOX}\n[[objective]]\nquantity = \"net_power\"\n");
    let e = Spec::from_str(&text, "box.opt.toml", m.dir.path()).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("box.opt.toml") && e.contains("variable[0]") && e.contains("not several"), "{e}");
}

#[test]
fn the_shipped_portal_frame_puts_its_frame_on_girder_nodes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/portal-frame");
    let lc = beamflow::case::LoadedCase::load(&dir.join("portal-frame.toml")).unwrap();
    let model = beamflow::case::build_model(&lc).unwrap();
    let beamflow::actuator::Actuator::Frame(f) = &model.actuators[0] else { panic!("a frame") };
    let node = |l: &beamflow::structure::Location| match l {
        beamflow::structure::Location::Node { node, .. } => *node,
        other => panic!("{other} is no node"),
    };
    let legs = f.legs.unwrap();
    assert_eq!([node(&f.at.unwrap()), node(&legs[0]), node(&legs[1])], [27, 26, 28]);
    // The girder's 21 nodes but its two corners, where a leg would fall off it.
    let sw =
        Sweep::from_str(&std::fs::read_to_string(dir.join("girder.sweep.toml")).unwrap(), "girder.sweep.toml", &dir)
            .unwrap();
    assert_eq!(sw.parameters[0].values, (22..=40).map(f64::from).collect::<Vec<_>>());
}
