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
//! `{psd = "fra4", seed = 1, wavelengths = [1, 50]}` ([`crate::rail::geometry::irregularity`]).

use crate::rail::geometry::alignment::SegmentSpec;
use crate::rail::geometry::cant::TrackSpec;
use crate::rail::geometry::track_model::{
    generate_with, JointDip, RailSection, RailSupport, TrackMesh,
};
use crate::rail::vehicle::section::apply_vehicles;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::error::FemError;
use railfem_framework::limits;
use railfem_framework::modelfile::{ModelSection, SizePart};
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
    /// Track irregularity: one table or a list ([`crate::rail::geometry::irregularity::from_value`]).
    #[serde(default)]
    irregularity: Option<Value>,
}

fn apply_track(v: &Value, origin: &str, b: &mut ModelBuilder) -> Result<(), FemError> {
    let t: TrackSection = railfem_framework::keypath::from_value(v, origin, "track")?;
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
            Some(Arc::new(crate::rail::geometry::irregularity::from_value(
                v, &base, range, origin,
            )?))
        }
    };
    generate_with(b, Arc::new(track), &mesh, irregularity)?;
    Ok(())
}

/// The track's part of the model's size estimate: the meshed length over `element_length`
/// stations, each as [`crate::rail::geometry::track_model::check_mesh_size`] counts it (two rail nodes on a
/// rigid support, 12 DOFs on discrete supports, 18 with a slab or girder).; a bridge's
/// girders and piers ([`crate::rail::geometry::bridge::BridgeSpec::estimated_dofs`]); and every
/// irregularity entry's samples or rows ([`crate::rail::geometry::irregularity::estimate`]).
fn estimate_track(v: &Value, base: &std::path::Path) -> Vec<SizePart> {
    let Ok(t) = railfem_framework::keypath::from_value::<TrackSection>(v, "", "") else {
        return Vec::new();
    };
    let range = t
        .window
        .unwrap_or([0.0, t.segments.iter().map(SegmentSpec::length).sum()]);
    let length = range[1] - range[0];
    let h = t
        .element_length
        .unwrap_or(TrackMesh::default().element_length);
    let stations = length / h + 1.0;
    let support = t.support.unwrap_or(RailSupport::Rigid);
    let per_station = match &support {
        RailSupport::Rigid => 2.0 * limits::BYTES_PER_NODE,
        RailSupport::Discrete { .. } => 12.0 * limits::BYTES_PER_DOF,
        _ => 18.0 * limits::BYTES_PER_DOF,
    };
    let mut parts = vec![SizePart {
        what: format!(
            "[track]: {} rail stations",
            limits::fmt_num(stations.ceil())
        ),
        bytes: stations * per_station,
    }];
    if let RailSupport::Bridge(b) = &support {
        let dofs = b.estimated_dofs();
        parts.push(SizePart {
            what: format!(
                "[track] bridge: {} spans, {} DOFs of girders and piers",
                b.spans,
                limits::fmt_num(dofs)
            ),
            bytes: dofs * limits::BYTES_PER_DOF,
        });
    }
    if let Some(irr) = &t.irregularity {
        parts.extend(crate::rail::geometry::irregularity::estimate::estimate(
            irr, base, range,
        ));
    }
    parts
}

railfem_framework::inventory::submit! {
    ModelSection {
        key: "track",
        description: "a track: alignment segments, cant, rails and their supports",
        order: -10,
        apply: apply_track,
        estimate: Some(estimate_track),
    }
}

railfem_framework::inventory::submit! {
    ModelSection {
        key: "vehicle",
        description: "trains of vehicles (presets, vehicle files or inline bodies and suspensions) riding the track on wheel elements",
        order: 10,
        apply: apply_vehicles,
        estimate: Some(crate::rail::vehicle::section::estimate_vehicles),
    }
}
