//! `[[vehicle]]` in a model file: a train of vehicles, each a preset (`preset = "sks700"`,
//! with `carriage = {...}` overrides of the template), a vehicle file
//! (`file = "vehicles/x.toml"`, relative to the model file) or an inline definition
//! (`[[vehicle.body]]`, `[[vehicle.suspension]]`, ...), repeated `count` times, coupled in
//! the order given; plus the train's motion, wheel keys, couplers and recorders.
//!
//! A train of one kind writes the vehicle keys on `[[vehicle]]` itself; a mixed train
//! lists them: `vehicles = [{preset = "sks700", count = 2}, {file = "v.toml"}]`.

use super::build::{self, CouplerDef, Train};
use super::comfort::{recorder::ComfortParams, ComfortMethod};
use super::definition::VehicleDef;
use super::track_model::TrackModel;
use super::{build_train_at, CarriageData, TrainSpec};
use crate::suspension::SuspensionTangent;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::dof::{Dof, DofSet};
use railfem_framework::error::FemError;
use railfem_framework::keypath::{self, from_value};
use railfem_framework::limits;
use railfem_framework::model::Geometry;
use railfem_framework::modelfile::SizePart;
use railfem_framework::recorder::{Quantity, RecorderSpec};
use serde::Deserialize;
use serde_json::{Map, Value};
use std::path::Path;
use std::sync::Arc;

/// The `sks700` preset written body by body (the template's numbers). It lives in the crate
/// (`elements/presets/`) so the published crate builds; `examples/vehicles/sks700.toml` links to it.
pub const SKS700_TOML: &str = include_str!("../../../presets/sks700.toml");

/// Keys of a vehicle unit that are not part of a definition.
const UNIT_KEYS: [&str; 5] = ["preset", "carriage", "file", "count", "carriages"];
/// Keys of the train.
const TRAIN_KEYS: [&str; 13] = [
    "name",
    "start",
    "speed",
    "accel",
    "speed_table",
    "wheel",
    "first_node_id",
    "geometry",
    "suspension_tangent",
    "coupler",
    "record",
    "vehicles",
    "defects",
];

/// Where a train's results go: `wheels` (every wheel's outputs), `sensors` (the sensor
/// points' accelerations) and `comfort` (the ride-comfort index at every sensor, by
/// `comfort_method`), file names relative to the output directory.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Record {
    #[serde(default)]
    wheels: Option<String>,
    #[serde(default)]
    sensors: Option<String>,
    #[serde(default)]
    comfort: Option<String>,
    #[serde(default)]
    comfort_method: Option<ComfortMethod>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TrainKeys {
    #[serde(default = "default_name")]
    name: String,
    start: f64,
    #[serde(default)]
    speed: Option<f64>,
    #[serde(default)]
    accel: f64,
    #[serde(default)]
    speed_table: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    wheel: Map<String, Value>,
    #[serde(default)]
    first_node_id: u64,
    #[serde(default)]
    geometry: Option<Geometry>,
    #[serde(default = "default_tangent")]
    suspension_tangent: SuspensionTangent,
    #[serde(default)]
    coupler: Option<CouplerDef>,
    #[serde(default)]
    record: Option<Record>,
    #[serde(default)]
    vehicles: Option<Vec<Value>>,
    /// Defects of single wheels of single vehicles ([`super::instance_defect`]).
    #[serde(default)]
    defects: Vec<super::instance_defect::InstanceDefect>,
}

/// The built-in vehicles a `[[vehicle]]` entry names with `preset`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
enum Preset {
    /// The sks700 carriage of the paper (`"sks700"`).
    Sks700,
}

fn default_name() -> String {
    "train".into()
}
fn default_tangent() -> SuspensionTangent {
    SuspensionTangent::Symmetric
}

/// Deep merge of `patch` into `base` (tables merge key by key, anything else replaces).
fn merge(base: &mut Value, patch: &Value) {
    match (base, patch) {
        (Value::Object(b), Value::Object(p)) => {
            for (k, v) in p {
                merge(b.entry(k.clone()).or_insert(Value::Null), v);
            }
        }
        (b, p) => *b = p.clone(),
    }
}

/// Parses a vehicle file's text (`name` for messages) into a normalized, validated
/// definition.
pub fn parse_vehicle(text: &str, name: &str) -> Result<VehicleDef, FemError> {
    let v = railfem_framework::modelfile::parse_toml(text, name)?;
    definition_from(&v, name, "")
}

/// A definition from its value at key path `at` (`""`: a vehicle file's top level).
fn definition_from(v: &Value, place: &str, at: &str) -> Result<VehicleDef, FemError> {
    let d: VehicleDef = from_value(v, place, at)?;
    let d = d.normalized();
    d.validate()
        .map_err(|(p, m)| FemError::input(format!("{place} {p}"), m))?;
    Ok(d)
}

/// The `sks700` preset as a definition (from [`SKS700_TOML`]).
pub fn sks700() -> Result<VehicleDef, FemError> {
    parse_vehicle(SKS700_TOML, "preset sks700 (examples/vehicles/sks700.toml)")
}

/// One vehicle unit (a table with `preset`, `file` or inline keys, and `count`) into its
/// definition and count. `o` is the place, `dir` the model file's directory.
fn unit(
    map: &Map<String, Value>,
    o: &str,
    at: &str,
    dir: &Path,
) -> Result<(VehicleDef, usize), FemError> {
    let count_key = if map.contains_key("carriages") {
        "carriages"
    } else {
        "count"
    };
    let count = match map.get(count_key) {
        None => 1,
        Some(v) => v.as_u64().map(|n| n as usize).ok_or_else(|| {
            FemError::input(o, format!("`{count_key}` must be a whole number ≥ 1"))
        })?,
    };
    if count == 0 {
        return Err(FemError::input(
            o,
            format!("`{count_key}` must be at least 1"),
        ));
    }
    // Size guard before the vehicles are repeated: a carriage is 66 DOFs (bodies, wheels'
    // contact nodes); a vehicle's own size is checked again when it is built.
    railfem_framework::limits::check_memory(
        &format!("`{count_key}` = {count}"),
        66.0 * count as f64,
        "vehicle DOFs",
        railfem_framework::limits::BYTES_PER_DOF,
        &format!("give fewer `{count_key}`"),
    )
    .map_err(|m| FemError::input(o, m))?;
    let inline: Map<String, Value> = map
        .iter()
        .filter(|(k, _)| !UNIT_KEYS.contains(&k.as_str()))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let sources = [
        map.contains_key("preset"),
        map.contains_key("file"),
        !inline.is_empty(),
    ];
    if sources.iter().filter(|s| **s).count() > 1 {
        return Err(FemError::input(
            o,
            "give one of `preset`, `file` or an inline definition (`body`, `suspension`, ...), not several",
        ));
    }
    if map.contains_key("carriage") && !map.contains_key("preset") && sources.iter().any(|s| *s) {
        return Err(FemError::input(o, "`carriage` overrides only apply to `preset = \"sks700\"`; remove `carriage` or the other source"));
    }
    if let Some(f) = map.get("file") {
        let rel = f.as_str().ok_or_else(|| {
            FemError::input(
                o,
                "`file` must be a path (text), relative to the model file",
            )
        })?;
        let path = dir.join(rel);
        let name = path.display().to_string();
        railfem_framework::limits::check_file(&path, "the vehicle file")
            .map_err(|m| FemError::input(format!("{o} `file`"), m))?;
        let text = std::fs::read_to_string(&path).map_err(|e| {
            FemError::input(
                format!("{o} `file`"),
                format!("cannot read the vehicle file {name}: {e}; give a path relative to the model file"),
            )
        })?;
        return Ok((parse_vehicle(&text, &name)?, count));
    }
    if !inline.is_empty() {
        return Ok((definition_from(&Value::Object(inline), o, at)?, count));
    }
    if let Some(p) = map.get("preset") {
        // One preset so far; a closed choice all the same, refused with the list.
        let Preset::Sks700 = from_value::<Preset>(p, o, &keypath::join(at, "preset"))?;
    }
    match map.get("carriage") {
        None => Ok((sks700()?, count)),
        Some(over) => {
            let mut c = serde_json::to_value(CarriageData::sks700()).unwrap_or(Value::Null);
            merge(&mut c, over);
            let c: CarriageData = from_value(&c, o, &keypath::join(at, "carriage"))?;
            c.validate().map_err(|m| FemError::input(o, m))?;
            Ok((c.expand(), count))
        }
    }
}

/// Applies `[[vehicle]]` (see the module documentation).
pub fn apply_vehicles(v: &Value, origin: &str, b: &mut ModelBuilder) -> Result<(), FemError> {
    let list: Vec<&Value> = match v {
        Value::Array(a) => a.iter().collect(),
        o @ Value::Object(_) => vec![o],
        _ => {
            return Err(FemError::input(
                origin,
                "`vehicle` must be an array of tables ([[vehicle]])",
            ))
        }
    };
    let dir = Path::new(b.origin())
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    for (i, item) in list.into_iter().enumerate() {
        let o = format!("{origin}[{i}]");
        let Value::Object(map) = item else {
            return Err(FemError::input(&o, "must be a table"));
        };
        let track =
            track_of(b).ok_or_else(|| FemError::input(&o, "a vehicle needs a [track] table"))?;
        if map.contains_key("carriage") && !map.contains_key("vehicles") {
            legacy(map, &o, &format!("vehicle[{i}]"), b, &track)?;
            continue;
        }
        let train_map: Map<String, Value> = map
            .iter()
            .filter(|(k, _)| TRAIN_KEYS.contains(&k.as_str()))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        let at = format!("vehicle[{i}]");
        let keys: TrainKeys = from_value(&Value::Object(train_map), &o, &at)?;
        let named = format!("{o} (vehicle `{}`)", keys.name);
        if keys.wheel.contains_key("side") {
            return Err(FemError::input(
                &o,
                "`wheel.side` would be ignored: the vehicle makes a left and a right wheel on every axle; remove `side` from the `wheel` table",
            ));
        }
        let unit_map: Map<String, Value> = map
            .iter()
            .filter(|(k, _)| !TRAIN_KEYS.contains(&k.as_str()))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        // Every entry's definition and count first; the vehicles are repeated only once the
        // whole train's size is known to fit.
        let mut units = Vec::new();
        match &keys.vehicles {
            Some(list) => {
                if !unit_map.is_empty() {
                    return Err(FemError::input(&o, "with `vehicles = [...]` give the vehicle keys in its entries, not on [[vehicle]]"));
                }
                for (j, u) in list.iter().enumerate() {
                    let ou = format!("{named} vehicles[{j}]");
                    let Value::Object(um) = u else {
                        return Err(FemError::input(&ou, "must be a table"));
                    };
                    units.push(unit(um, &ou, &format!("{at}.vehicles[{j}]"), &dir)?);
                }
            }
            None => units.push(unit(&unit_map, &named, &at, &dir)?),
        }
        check_train_size(&units, &at).map_err(|m| FemError::input(&named, m))?;
        let mut vehicles = Vec::new();
        for (d, n) in units {
            vehicles.extend(std::iter::repeat_n(d, n));
        }
        super::instance_defect::apply(&mut vehicles, &keys.defects, &named, &at)?;
        let train = Train {
            name: keys.name.clone(),
            vehicles,
            coupler: keys.coupler.unwrap_or_default(),
            start: keys.start,
            speed: motion(keys.speed, keys.accel, keys.speed_table.is_some(), &named)?,
            accel: keys.accel,
            speed_table: keys.speed_table.clone(),
            wheel: keys.wheel.clone(),
            first_node_id: keys.first_node_id,
            geometry: keys.geometry,
            suspension_tangent: keys.suspension_tangent,
        };
        let ids = build::build(b, &track, &train, &named)?;
        publish_sensors(b, &keys.name, &ids);
        if let Some(r) = keys.record {
            record(b, &ids, &r, &named)?;
        }
    }
    Ok(())
}

/// The size guard of a whole train, from its entries' definitions and counts before any
/// vehicle is repeated: the DOFs of all of them ([`VehicleDef::dofs`]) against the memory
/// budget. `at` is the train's key path. Returns the message.
fn check_train_size(units: &[(VehicleDef, usize)], at: &str) -> Result<(), String> {
    let vehicles: f64 = units.iter().map(|(_, n)| *n as f64).sum();
    let dofs: f64 = units.iter().map(|(d, n)| d.dofs() as f64 * *n as f64).sum();
    let entries = if units.len() == 1 {
        String::new()
    } else {
        format!(" in {} entries of `vehicles`", units.len())
    };
    railfem_framework::limits::check_memory(
        &format!("`{at}`: {} vehicles{entries}", limits::fmt_num(vehicles)),
        dofs,
        "vehicle DOFs",
        limits::BYTES_PER_DOF,
        "give fewer vehicles (`count` of each entry)",
    )
}

/// The trains' part of the model's size estimate, from the `[[vehicle]]` value alone: every
/// entry's count times its vehicle's DOFs ([`VehicleDef::dofs`]; a vehicle file is read
/// for its bodies, wheelsets and sensors). `dir` is the model file's folder. Entries that
/// will be refused count as nothing.
pub fn estimate_vehicles(v: &Value, dir: &Path) -> Vec<SizePart> {
    let trains: Vec<&Value> = match v {
        Value::Array(a) => a.iter().collect(),
        o => vec![o],
    };
    let mut out = Vec::new();
    for (i, t) in trains.into_iter().enumerate() {
        let Value::Object(map) = t else { continue };
        let units: Vec<&Map<String, Value>> = match map.get("vehicles") {
            Some(Value::Array(a)) => a.iter().filter_map(Value::as_object).collect(),
            _ => vec![map],
        };
        let (mut vehicles, mut dofs) = (0.0, 0.0);
        for u in units {
            let count = ["carriages", "count"]
                .iter()
                .find_map(|k| u.get(*k))
                .map_or(Some(1), Value::as_u64)
                .unwrap_or(0) as f64;
            vehicles += count;
            dofs += count * unit_dofs(u, dir) as f64;
        }
        out.push(SizePart {
            what: format!(
                "vehicle[{i}]: {} vehicles, {} DOFs",
                limits::fmt_num(vehicles),
                limits::fmt_num(dofs)
            ),
            bytes: dofs * limits::BYTES_PER_DOF,
        });
    }
    out
}

/// DOFs of one vehicle of a unit table, from its value: the preset's, or those of the
/// bodies, wheelsets and sensors its file or inline definition lists (0 if unreadable).
fn unit_dofs(u: &Map<String, Value>, dir: &Path) -> usize {
    let listed = |m: &Map<String, Value>| {
        let n = |k: &str| m.get(k).and_then(Value::as_array).map_or(0, Vec::len);
        6 * (n("body") + 2 * n("wheelset") + n("sensor"))
    };
    if let Some(f) = u.get("file").and_then(Value::as_str) {
        let path = dir.join(f);
        if limits::check_file(&path, "").is_err() {
            return 0;
        }
        return std::fs::read_to_string(&path)
            .ok()
            .and_then(|t| railfem_framework::modelfile::parse_toml(&t, "").ok())
            .and_then(|v| v.as_object().map(listed))
            .unwrap_or(0);
    }
    if u.contains_key("body") {
        return listed(u);
    }
    static PRESET: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *PRESET.get_or_init(|| CarriageData::sks700().expand().dofs())
}

/// Name of the builder resource listing every train's sensor nodes as
/// `("<train>/<sensor>", node id)`: the hook a comfort recorder finds them by.
pub const SENSORS_RESOURCE: &str = "vehicle_sensors";

/// Appends the train's sensors to [`SENSORS_RESOURCE`].
fn publish_sensors(b: &mut ModelBuilder, train: &str, ids: &super::TrainIds) {
    let mut all: Vec<(String, u64)> = b
        .resource_get(SENSORS_RESOURCE)
        .and_then(|r| r.downcast::<Vec<(String, u64)>>().ok())
        .map(|a| (*a).clone())
        .unwrap_or_default();
    all.extend(
        ids.sensors
            .iter()
            .map(|(n, id)| (format!("{train}/{n}"), *id)),
    );
    b.resource(SENSORS_RESOURCE, Arc::new(all));
}

/// `record = {wheels, sensors, comfort}`: an element recorder of the train's wheels (all
/// their outputs), a node recorder of the sensors' accelerations and a `comfort` recorder
/// of the sensors (vehicle nodes' axes: `ux` lateral, `uy` vertical, `uz` longitudinal).
fn record(
    b: &mut ModelBuilder,
    ids: &super::TrainIds,
    r: &Record,
    o: &str,
) -> Result<(), FemError> {
    if let Some(f) = &r.wheels {
        b.recorder(RecorderSpec::Element {
            element: None,
            elements: ids.wheels.clone(),
            kind: None,
            outputs: Vec::new(),
            file: f.clone(),
        });
    }
    if let Some(f) = &r.sensors {
        if ids.sensors.is_empty() {
            return Err(FemError::input(
                format!("{o} record.sensors"),
                "the train has no sensors; add [[vehicle.sensor]] entries (name, body, at) or remove `record.sensors`",
            ));
        }
        b.recorder(RecorderSpec::Node {
            node: None,
            nodes: ids.sensors.iter().map(|s| s.1).collect(),
            dofs: DofSet::TRANSLATIONS,
            quantity: Quantity::Acc,
            file: f.clone(),
        });
    }
    if r.comfort_method.is_some() && r.comfort.is_none() {
        return Err(FemError::input(
            format!("{o} record.comfort_method"),
            "`comfort_method` needs `comfort = \"file.csv\"` beside it (the file the index goes to)",
        ));
    }
    if let Some(f) = &r.comfort {
        if ids.sensors.is_empty() {
            return Err(FemError::input(
                format!("{o} record.comfort"),
                "the ride-comfort index is taken at the train's sensors and it has none; add [[vehicle.sensor]] entries (name, body, at) or remove `record.comfort`",
            ));
        }
        let method = r.comfort_method.unwrap_or_default();
        // Sperling has no longitudinal weighting; EN 12299 uses all three axes.
        let longitudinal = if method == ComfortMethod::En12299 {
            vec![Dof::Uz]
        } else {
            Vec::new()
        };
        let sensors: Vec<u64> = ids.sensors.iter().map(|s| s.1).collect();
        b.recorder(
            ComfortParams {
                longitudinal,
                method,
                ..ComfortParams::new(&sensors, &[Dof::Uy], &[Dof::Ux])
            }
            .spec(f.clone()),
        );
    }
    Ok(())
}

/// The train's speed at t = 0 from its motion keys: `speed` (with `accel`), or a
/// `speed_table` instead of both (its own first row gives the speed; the value returned
/// then is a placeholder the table replaces). `o` names the place.
fn motion(speed: Option<f64>, accel: f64, table: bool, o: &str) -> Result<f64, FemError> {
    match (speed, table) {
        (Some(v), false) => Ok(v),
        (None, true) if accel == 0.0 => Ok(0.0),
        (None, true) => Err(FemError::input(
            o,
            "`accel` and `speed_table` both set the motion; give the braking or accelerating in the table's rows and remove `accel`",
        )),
        (Some(_), true) => Err(FemError::input(
            o,
            "`speed` and `speed_table` both set the motion; remove `speed` (the table's first row is the speed at t = 0)",
        )),
        (None, false) => Err(FemError::input(
            o,
            "the train needs its motion: `speed` (m/s, with an optional `accel` in m/s²) or `speed_table = [[t s, v m/s], …]`",
        )),
    }
}

/// The template route: `preset` with `carriage` overrides and `carriages`, exactly as
/// before the generic definition (its messages name the template's keys).
fn legacy(
    map: &Map<String, Value>,
    o: &str,
    at: &str,
    b: &mut ModelBuilder,
    track: &Arc<TrackModel>,
) -> Result<(), FemError> {
    let mut map = map.clone();
    let preset = map.remove("preset");
    let mut carriage = match preset.as_ref().and_then(Value::as_str) {
        Some("sks700") | None => {
            serde_json::to_value(CarriageData::sks700()).unwrap_or(Value::Null)
        }
        Some(other) => {
            return Err(FemError::input(
                o,
                format!("unknown preset `{other}`; the presets are: sks700"),
            ))
        }
    };
    if let Some(over) = map.remove("carriage") {
        merge(&mut carriage, &over);
    }
    let rec: Option<Record> = match map.remove("record") {
        Some(r) => Some(from_value(&r, o, &keypath::join(at, "record"))?),
        None => None,
    };
    let speed = map.get("speed").and_then(Value::as_f64);
    let accel = map.get("accel").and_then(Value::as_f64).unwrap_or(0.0);
    let speed = motion(speed, accel, map.contains_key("speed_table"), o)?;
    map.insert("speed".into(), Value::from(speed));
    map.insert("carriage".into(), carriage);
    map.entry("carriages").or_insert(Value::from(1));
    map.entry("wheel")
        .or_insert(Value::Object(Default::default()));
    let spec: TrainSpec = from_value(&Value::Object(map), o, at)?;
    if let Value::Object(w) = &spec.wheel {
        if w.contains_key("side") {
            return Err(FemError::input(
                o,
                "`wheel.side` would be ignored: the vehicle makes a left and a right wheel on every axle; remove `side` from the `wheel` table",
            ));
        }
    }
    let named = format!("{o} (vehicle `{}`)", spec.name);
    let ids = build_train_at(b, track, &spec, &named)?;
    if let Some(r) = rec {
        record(b, &ids, &r, &named)?;
    }
    Ok(())
}

fn track_of(b: &ModelBuilder) -> Option<Arc<TrackModel>> {
    b.resource_get("track")
        .and_then(|r| r.downcast::<TrackModel>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `examples/vehicles/sks700.toml`, the preset written body by body, parses to exactly
    /// (f64 ==) the expansion of `CarriageData::sks700()`: every mass, inertia, position,
    /// rate, damper and share, in the same order.
    #[test]
    fn sks700_file_equals_the_template_expansion() {
        let mut parsed = sks700().expect("the preset file parses");
        let expanded = CarriageData::sks700().expand();
        parsed.description = expanded.description.clone();
        assert_eq!(parsed, expanded);
    }

    /// `mirror` writes the image at −y right after the spring, `_left` becoming `_right`.
    #[test]
    fn mirror_expands_in_place() {
        let v = sks700().expect("parses");
        let names: Vec<&str> = v
            .suspensions
            .iter()
            .filter_map(|s| s.name.as_deref())
            .collect();
        assert_eq!(
            &names[..4],
            [
                "secondary_front_left",
                "secondary_front_right",
                "primary_1_left",
                "primary_1_right"
            ]
        );
        assert_eq!(v.suspensions[1].at[1], -v.suspensions[0].at[1]);
    }
}
