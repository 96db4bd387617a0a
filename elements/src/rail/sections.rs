//! The rail toolkit's model-file sections: `[track]` (alignment, cant, rails, supports) and
//! `[[vehicle]]` (trains of carriages on moving-axle wheels), registered with the
//! framework's model-file reader like any other section.
//!
//! ```toml
//! [track]
//! segments = [{type = "straight", length = 500}, {type = "clothoid", length = 2000},
//!             {type = "arc", length = 10908.3078, radius = 6250, hand = "left"},
//!             {type = "clothoid", length = 2000}, {type = "straight", length = 800}]
//! ct = 200                 # cant θ = Ct/R (Eq. 21), m
//! element_length = 0.6     # m
//! support = {type = "rigid"}
//!
//! [[vehicle]]
//! preset = "sks700"        # stand-in data; any key of `carriage` overrides it
//! carriages = 1
//! start = 30.0             # m
//! speed = 80.0             # m/s
//! wheel = {mu = 0.3}       # moving_axle keys
//! ```
//!
//! `[track] irregularity` takes a table or a list of tables, `{file = "irr.csv"}` or
//! `{psd = "fra4", seed = 1, wavelengths = [1, 50]}` ([`super::irregularity`]).

use super::alignment::SegmentSpec;
use super::cant::TrackSpec;
use super::track_model::{
    generate_with, JointDip, RailSection, RailSupport, TrackMesh, TrackModel,
};
use super::vehicle::{build_train_at, CarriageData, TrainSpec};
use railfem_framework::error::FemError;
use railfem_framework::model::ModelBuilder;
use railfem_framework::modelfile::ModelSection;
use serde::Deserialize;
use serde_json::Value;
use std::sync::Arc;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TrackSection {
    segments: Vec<SegmentSpec>,
    #[serde(default)]
    ct: Option<f64>,
    #[serde(default)]
    cant_table: Option<Vec<(f64, f64)>>,
    #[serde(default)]
    gauge: Option<f64>,
    #[serde(default)]
    element_length: Option<f64>,
    #[serde(default)]
    rail_offset: Option<f64>,
    #[serde(default)]
    rail: Option<RailSection>,
    #[serde(default)]
    support: Option<RailSupport>,
    #[serde(default)]
    window: Option<[f64; 2]>,
    #[serde(default)]
    dips: Vec<JointDip>,
    /// Track irregularity: one table or a list ([`super::irregularity::from_value`]).
    #[serde(default)]
    irregularity: Option<Value>,
}

fn apply_track(v: &Value, origin: &str, b: &mut ModelBuilder) -> Result<(), FemError> {
    let t: TrackSection =
        TrackSection::deserialize(v).map_err(|e| FemError::input(origin, e.to_string()))?;
    let spec = TrackSpec {
        segments: t.segments,
        ct: t.ct,
        cant_table: t.cant_table,
        gauge: t.gauge.unwrap_or(1.435),
    };
    let track = spec
        .build()
        .map_err(|e| FemError::input(origin, e.to_string()))?;
    let d = TrackMesh::default();
    let mesh = TrackMesh {
        element_length: t.element_length.unwrap_or(d.element_length),
        rail_offset: t.rail_offset,
        rail: t.rail.unwrap_or(d.rail),
        support: t.support.unwrap_or(d.support),
        window: t.window,
        dips: t.dips,
    };
    let irregularity = match &t.irregularity {
        None => None,
        Some(v) => {
            // Files are relative to the model file (the builder's origin is its path).
            let base = std::path::Path::new(b.origin())
                .parent()
                .map(std::path::Path::to_path_buf)
                .unwrap_or_default();
            let range = mesh.window.unwrap_or([0.0, track.alignment.length()]);
            Some(Arc::new(super::irregularity::from_value(
                v, &base, range, origin,
            )?))
        }
    };
    generate_with(b, Arc::new(track), &mesh, irregularity)?;
    Ok(())
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

fn apply_vehicles(v: &Value, origin: &str, b: &mut ModelBuilder) -> Result<(), FemError> {
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
    for (i, item) in list.into_iter().enumerate() {
        let o = format!("{origin}[{i}]");
        let Value::Object(map) = item else {
            return Err(FemError::input(&o, "must be a table"));
        };
        let mut map = map.clone();
        let preset = map.remove("preset");
        let mut carriage = match preset.as_ref().and_then(Value::as_str) {
            Some("sks700") | None => {
                serde_json::to_value(CarriageData::sks700()).unwrap_or(Value::Null)
            }
            Some(other) => {
                return Err(FemError::input(
                    &o,
                    format!("unknown preset `{other}`; the presets are: sks700"),
                ))
            }
        };
        if let Some(over) = map.remove("carriage") {
            merge(&mut carriage, &over);
        }
        map.insert("carriage".into(), carriage);
        map.entry("carriages").or_insert(Value::from(1));
        map.entry("wheel")
            .or_insert(Value::Object(Default::default()));
        let spec: TrainSpec = TrainSpec::deserialize(Value::Object(map))
            .map_err(|e| FemError::input(&o, e.to_string()))?;
        let track =
            track_of(b).ok_or_else(|| FemError::input(&o, "a vehicle needs a [track] table"))?;
        if let Value::Object(w) = &spec.wheel {
            if w.contains_key("side") {
                return Err(FemError::input(
                    &o,
                    "`wheel.side` would be ignored: the vehicle makes a left and a right wheel on every axle; remove `side` from the `wheel` table",
                ));
            }
        }
        build_train_at(b, &track, &spec, &format!("{o} (vehicle `{}`)", spec.name))?;
    }
    Ok(())
}

fn track_of(b: &ModelBuilder) -> Option<Arc<TrackModel>> {
    b.resource_get("track")
        .and_then(|r| r.downcast::<TrackModel>().ok())
}

railfem_framework::inventory::submit! {
    ModelSection {
        key: "track",
        description: "a track: alignment segments, cant, rails and their supports",
        order: -10,
        apply: apply_track,
    }
}

railfem_framework::inventory::submit! {
    ModelSection {
        key: "vehicle",
        description: "trains of carriages riding the track on moving-axle wheels",
        order: 10,
        apply: apply_vehicles,
    }
}
