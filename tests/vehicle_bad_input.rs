//! Bad input in generic vehicle definitions (inline `[[vehicle.body]]` ... or a vehicle
//! file): each is refused before anything is built with one line naming the model file,
//! the place inside the vehicle and the fix, exit code 2.

mod common;
use common::check_bad_model;

/// A rigid straight with one vehicle written inline: a car body on one wheelset by two
/// springs (the smallest vehicle the checks see); `patch` replaces a marked line.
fn model(body: &str, susp: &str, wheelset: &str) -> String {
    format!(
        r#"
[analysis]
kind = "static"
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 60.0}}]
support = {{type = "rigid"}}

[[vehicle]]
start = 30.0
speed = 0.0
length = 6.0

[[vehicle.body]]
name = "car"
mass = 5000.0
ixx = 2000.0
iyy = 8000.0
izz = 8000.0
z = 1.2

{body}

[[vehicle.suspension]]
name = "spring"
{susp}
at = [0.0, 1.0, 0.6]
k = [1e6, 1e6, 1e6]
mirror = true

{wheelset}
"#
    )
}

const WS_BODY: &str = r#"[[vehicle.body]]
name = "axle"
mass = 1500.0
ixx = 800.0
iyy = 100.0
izz = 800.0
z = 0.45"#;
const SUSP: &str = "lower = \"axle\"\nupper = \"car\"";
const WS: &str = "[[vehicle.wheelset]]\nbody = \"axle\"";

#[test]
fn suspension_naming_a_missing_body() {
    check_bad_model(
        "susp_body.toml",
        &model(WS_BODY, "lower = \"axel\"\nupper = \"car\"", WS),
        &[
            "[vehicle][0]",
            "suspension[0] \"spring\"",
            "`lower` names body \"axel\", which does not exist",
            "the bodies are: car, axle",
        ],
    );
}

#[test]
fn negative_mass() {
    check_bad_model(
        "neg_mass.toml",
        &model(&WS_BODY.replace("1500.0", "-1500.0"), SUSP, WS),
        &[
            "body \"axle\"",
            "`mass` = -1500",
            "give a positive mass (kg)",
        ],
    );
}

#[test]
fn inertia_not_positive_definite() {
    // Products larger than the moments: ixx·iyy − ixy² < 0.
    let body = format!("{WS_BODY}\nixy = 900.0");
    check_bad_model(
        "inertia.toml",
        &model(&body, SUSP, WS),
        &[
            "body \"axle\"",
            "not positive definite",
            "give positive moments larger than the products",
        ],
    );
    check_bad_model(
        "inertia0.toml",
        &model(&WS_BODY.replace("iyy = 100.0", "iyy = 0.0"), SUSP, WS),
        &["body \"axle\"", "not positive definite"],
    );
}

#[test]
fn duplicate_body_names() {
    check_bad_model(
        "dup.toml",
        &model(&format!("{WS_BODY}\n\n{}", WS_BODY), SUSP, WS),
        &[
            "body \"axle\"",
            "appears twice",
            "give every body its own name",
        ],
    );
}

#[test]
fn unknown_wheel_model() {
    check_bad_model(
        "wheel_model.toml",
        &model(
            WS_BODY,
            SUSP,
            &format!("{WS}\nwheel = {{model = \"elastic\"}}"),
        ),
        &[
            "wheelset[0]",
            "`wheel.model`: unknown variant `elastic`",
            "`moving_axle`, `hertz_wheel`, `rigid_wheel`",
        ],
    );
}

#[test]
fn wheel_off_the_rail_mesh() {
    let text = model(WS_BODY, SUSP, WS).replace("start = 30.0", "start = 75.0");
    check_bad_model(
        "off_mesh.toml",
        &text,
        &[
            "wheelset[0] (body \"axle\")",
            "`start` = 75: the wheelset starts at station 75 m",
            "move `start` or lengthen the track",
        ],
    );
}

#[test]
fn contact_point_off_the_rail_head() {
    check_bad_model(
        "off_head.toml",
        &model(WS_BODY, SUSP, &format!("{WS}\ncontact_offset = 0.9")),
        &[
            "wheelset[0] (body \"axle\")",
            "`contact_offset` = 0.9",
            "off the rail head",
            "give a contact offset within the head",
        ],
    );
}

#[test]
fn missing_vehicle_file() {
    let text = r#"
[track]
segments = [{type = "straight", length = 60.0}]
support = {type = "rigid"}

[[vehicle]]
file = "vehicles/none.toml"
start = 30.0
speed = 0.0
"#;
    check_bad_model(
        "no_file.toml",
        text,
        &[
            "[vehicle][0]",
            "`file`",
            "vehicles/none.toml",
            "give a path relative to the model file",
        ],
    );
}

#[test]
fn vehicle_without_wheelsets() {
    check_bad_model(
        "no_ws.toml",
        &model(WS_BODY, SUSP, ""),
        &[
            "[vehicle][0]",
            "no wheelsets",
            "give at least one [[wheelset]]",
        ],
    );
}

#[test]
fn force_table_not_sorted_and_bad_bump_stop() {
    let susp = format!("{SUSP}\nforce_table = {{z = [[0.0, 0.0], [-0.05, -1e4]]}}");
    check_bad_model(
        "table.toml",
        &model(WS_BODY, &susp, WS),
        &[
            "suspension[0] \"spring\"",
            "`force_table.z`[1]",
            "does not increase",
            "sort the points",
        ],
    );
    let susp = format!("{SUSP}\nbump_stop = {{w = {{gap = 0.02, k = 1e6}}}}");
    check_bad_model(
        "stop.toml",
        &model(WS_BODY, &susp, WS),
        &[
            "suspension[0].bump_stop.w`",
            "unknown variant `w`",
            "`x`, `y`, `z`, `rx`, `ry`, `rz`",
        ],
    );
    let susp = format!("{SUSP}\nbump_stop = {{y = {{gap = -0.02, k = 1e6}}}}");
    check_bad_model(
        "stop_gap.toml",
        &model(WS_BODY, &susp, WS),
        &["`bump_stop.y`", "≥ 0"],
    );
}
