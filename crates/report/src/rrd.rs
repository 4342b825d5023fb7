//! Trials written to Rerun recordings (`.rrd` files, or a live Rerun viewer),
//! to scrub through on the simulated-time timeline `sim_time`:
//! - `world/robot/<link>`: each robot link as its URDF collision shapes,
//!   posed every camera frame, and `world/robot/bones` joining its joints;
//! - `world/beacon`, `world/approach` (the line of approach with the ends of
//!   the test range) and `world/floor` (a grid);
//! - `world/camera`: the head camera (a pinhole, posed every frame) with its
//!   image and the measured extent of the band;
//! - `series/...`: the command, the reading, the true distance, the learner's
//!   `x_a`, `x_s` and the filter's estimate (after the sensor metric's best
//!   affine map into mm), and both models' errors;
//! - `models/action` and `models/sensor`: the learned models against the
//!   measured ones, as they change.
//!
//! The recording opens with a layout of these views. Built with the `rerun`
//! feature.

use std::path::Path;

use quadsim::scene::{Placement, Role, Scene, Shape};
use quadsim::{QuadrupedSim, SimConfig};
use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView, Spatial3DView, TimePanel,
    TimeSeriesView, Vertical,
};
use rerun::{Color, RecordingStream};

use testbed::experiment::{self, RecordedTrial};
use testbed::metrics;
use testbed::reference::{Judgement, MeasuredModels, Reference};
use testbed::scenario::Scenario;
use testbed::trial::{FrameRecord, Recording, TraceRow, TrialError, TrialRunner};

use crate::ReportError;
use crate::paper::{action_chart, sensor_chart};
use crate::plot::{Drawing, encode_png};

/// The timeline everything is logged on.
pub const TIMELINE: &str = "sim_time";

/// How often the learned models are logged while writing a trial, s.
pub const MODELS_EVERY_S: f64 = 1.0;

/// A recording that could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RrdError {
    /// The Rerun SDK refused.
    #[error("rerun: {0}")]
    Rerun(#[from] rerun::RecordingStreamError),
    /// A camera image or a chart could not be drawn.
    #[error(transparent)]
    Picture(#[from] ReportError),
    /// The recording could not be flushed to its sink.
    #[error("finishing the recording: {0}")]
    Flush(String),
    /// The trial could not run.
    #[error(transparent)]
    Trial(#[from] TrialError),
    /// Re-simulated, the trial did not give the frames it gave before.
    #[error(
        "re-simulated, trial {seed} differs from its recording at frame {frame}: \
         this build's physics is not the one that recorded it"
    )]
    NotReproduced {
        /// The trial's seed.
        seed: u64,
        /// The first frame that differs.
        frame: usize,
    },
}

// Colours that read on Rerun's dark background.
const BLUE: [u8; 3] = [90, 140, 240];
const ORANGE: [u8; 3] = [255, 140, 0];
const GREY: [u8; 3] = [150, 150, 150];
const LIGHT: [u8; 3] = [110, 110, 105];
const GREEN: [u8; 3] = [40, 200, 60];
const WHITE: [u8; 3] = [235, 235, 235];
const PURPLE: [u8; 3] = [200, 120, 255];
const PALE_BLUE: [u8; 3] = [120, 160, 220];

fn colour([r, g, b]: [u8; 3]) -> Color {
    Color::from_rgb(r, g, b)
}

/// A trial being written to a Rerun recording.
#[derive(Debug)]
pub struct TrialLog {
    rec: RecordingStream,
    reference: Reference,
    /// The world's settings as last drawn (the scene is drawn again when
    /// they change).
    world: Option<SimConfig>,
    scene: Option<Scene>,
    /// The learner's units to mm, `(scale, offset)`: the sensor metric's best
    /// affine map for the last judged sensor model.
    gauge: Option<(f64, f64)>,
    /// The farthest test distance, m: sets the size of what is drawn.
    far_m: f64,
}

impl TrialLog {
    /// A recording saved to `path` (an `.rrd` file), of a trial judged
    /// against `models`.
    pub fn save(path: &Path, models: &MeasuredModels) -> Result<Self, RrdError> {
        Self::new(Self::builder().save(path)?, models)
    }

    /// A recording streamed to a Rerun viewer, started if none is running
    /// (the `rerun` command must be on the PATH).
    pub fn spawn(models: &MeasuredModels) -> Result<Self, RrdError> {
        Self::new(Self::builder().spawn()?, models)
    }

    /// A recording kept in memory (for tests and tools), with its storage.
    pub fn memory(
        models: &MeasuredModels,
    ) -> Result<(Self, rerun::sink::MemorySinkStorage), RrdError> {
        let (rec, storage) = Self::builder().memory()?;
        Ok((Self::new(rec, models)?, storage))
    }

    fn builder() -> rerun::RecordingStreamBuilder {
        rerun::RecordingStreamBuilder::new("scasm-testbed")
    }

    fn new(rec: RecordingStream, models: &MeasuredModels) -> Result<Self, RrdError> {
        let reference = models.reference();
        let worlds: Vec<(f64, &Reference)> = reference.worlds().collect();
        let span = |points: &mut dyn Iterator<Item = f64>| {
            points.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
        };
        let far_m = 1e-3 * span(&mut worlds.iter().flat_map(|w| w.1.sensor.iter().map(|p| p.0))).1;
        let log = Self {
            rec,
            reference: reference.clone(),
            world: None,
            scene: None,
            gauge: None,
            far_m,
        };
        log.layout()?;
        log.styles()?;
        for (at_s, world) in &worlds {
            log.rec.set_duration_secs(TIMELINE, at_s.max(0.0));
            log.models(world, None, None)?;
        }
        Ok(log)
    }

    /// The viewer's layout: the world and the camera on top, the series and
    /// the models below.
    fn layout(&self) -> Result<(), RrdError> {
        let top = Horizontal::new([
            Spatial3DView::new("robot and beacon (physics)")
                .with_origin("world")
                .into(),
            Spatial2DView::new("head camera: band and measured extent")
                .with_origin("world/camera")
                .into(),
        ])
        .with_column_shares([3.0, 2.0]);
        let middle = Horizontal::new([
            TimeSeriesView::new("distance to the beacon (mm)")
                .with_origin("series/distance")
                .into(),
            Spatial2DView::new("action model: learned (best scale) and measured")
                .with_origin("models/action")
                .into(),
            Spatial2DView::new("sensor model: learned (best affine map) and measured")
                .with_origin("models/sensor")
                .into(),
        ])
        .with_column_shares([2.0, 1.0, 1.0]);
        let bottom = Horizontal::new([
            TimeSeriesView::new("walk command (mm/s)")
                .with_origin("series/command")
                .into(),
            TimeSeriesView::new("reading (px)")
                .with_origin("series/reading")
                .into(),
            TimeSeriesView::new("model errors (mm/s, mm)")
                .with_origin("series/error")
                .into(),
        ]);
        let root = Vertical::new([top.into(), middle.into(), bottom.into()])
            .with_row_shares([5.0, 3.0, 2.0]);
        // Open at the latest moment (the end of a saved trial; live, the
        // newest frame), from which a user scrubs back.
        let time = TimePanel::new()
            .with_timeline(TIMELINE)
            .with_play_state(PlayState::Following);
        Blueprint::new(root)
            .with_time_panel(time)
            .with_blueprint_panel(BlueprintPanel::from_state(PanelState::Collapsed))
            .with_selection_panel(SelectionPanel::from_state(PanelState::Collapsed))
            .send(&self.rec, Default::default())?;
        Ok(())
    }

    /// Names and colours of the series.
    fn styles(&self) -> Result<(), RrdError> {
        for (path, name, c, width) in [
            (
                "series/distance/true",
                "true (never shown to the learner)",
                WHITE,
                2.0,
            ),
            ("series/distance/x_a", "x_a (dead reckoning)", BLUE, 1.5),
            ("series/distance/x_s", "x_s (sensor model)", ORANGE, 1.0),
            (
                "series/distance/filter",
                "filter with the learned models",
                PURPLE,
                1.5,
            ),
            ("series/command", "command", BLUE, 1.5),
            ("series/reading", "reading", ORANGE, 1.0),
            ("series/error/action", "action RMSE (mm/s)", BLUE, 2.0),
            ("series/error/sensor", "sensor RMSE (mm)", ORANGE, 2.0),
        ] {
            self.rec.log_static(
                path,
                &rerun::SeriesLines::new()
                    .with_names([name])
                    .with_colors([colour(c)])
                    .with_widths([width]),
            )?;
        }
        Ok(())
    }

    /// Logs the world after `frame`: the robot's pose, what the camera sees,
    /// the command, the reading and the true distance.
    pub fn world_frame(&mut self, sim: &QuadrupedSim, frame: &FrameRecord) -> Result<(), RrdError> {
        self.rec.set_duration_secs(TIMELINE, frame.end_s());
        if self.world.as_ref() != Some(sim.config()) {
            self.draw_scene(sim)?;
        }
        let Some(scene) = &self.scene else {
            return Ok(());
        };
        let placements = sim.placements();
        let unit = self.far_m / 3.6;
        let mut bones: Vec<Vec<[f32; 3]>> = Vec::new();
        for (body, at) in scene.bodies.iter().zip(&placements) {
            if !body.robot_link {
                continue;
            }
            self.rec
                .log(format!("world/robot/{}", body.name), &transform(at))?;
            if let Some(parent) = body.parent {
                bones.push(vec![
                    f32s(placements[parent].translation_m),
                    f32s(at.translation_m),
                ]);
            }
            // Out to parts set off from the link's origin (the feet).
            for part in &body.parts {
                let offset = part.in_body.translation_m;
                if offset.iter().map(|v| v * v).sum::<f64>() > (0.01 * unit).powi(2) {
                    bones.push(vec![f32s(at.translation_m), f32s(at.apply(offset))]);
                }
            }
        }
        self.rec.log(
            "world/robot/bones",
            &rerun::LineStrips3D::new(bones)
                .with_radii([(0.004 * unit) as f32])
                .with_colors([colour(BLUE)]),
        )?;
        self.rec
            .log("world/camera", &transform(&sim.camera_placement()))?;
        let intrinsics = sim.config().camera.intrinsics;
        let blob = sim.camera_blob();
        let rgb = quadsim::vision::render_rgb(&intrinsics, blob.as_ref());
        self.rec.log(
            "world/camera/image",
            &rerun::EncodedImage::from_file_contents(encode_png(
                &rgb,
                (intrinsics.width_px, intrinsics.height_px),
            )?)
            .with_media_type(rerun::MediaType::png()),
        )?;
        let extent: Vec<Vec<[f32; 2]>> = blob
            .iter()
            .flat_map(|b| {
                let (left, right) = (b.cols[0] as f32, b.cols[1] as f32 + 1.0);
                [b.rows[0] as f32, b.rows[1] as f32 + 1.0]
                    .map(|row| vec![[left - 3.0, row], [right + 3.0, row]])
            })
            .collect();
        let label = blob.map(|b| format!("{:.0} px", b.extent_px()));
        self.rec.log(
            "world/camera/extent",
            &rerun::LineStrips2D::new(extent)
                .with_colors([colour(GREEN)])
                .with_radii([0.6])
                .with_labels(label),
        )?;
        self.rec
            .log("series/command", &rerun::Scalars::single(frame.command))?;
        if let Some(obs) = frame.obs_px {
            self.rec
                .log("series/reading", &rerun::Scalars::single(obs))?;
        }
        self.rec.log(
            "series/distance/true",
            &rerun::Scalars::single(frame.truth.x_mm),
        )?;
        Ok(())
    }

    /// Draws the world's fixed parts and the robot's shapes (once, and again
    /// whenever the world's settings change).
    fn draw_scene(&mut self, sim: &QuadrupedSim) -> Result<(), RrdError> {
        let scene = sim.scene();
        let placements = sim.placements();
        let unit = self.far_m / 3.6;
        if self.world.is_none() {
            self.rec
                .log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())?;
            let intr = sim.config().camera.intrinsics;
            self.rec.log_static(
                "world/camera",
                &rerun::Pinhole::from_focal_length_and_resolution(
                    [intr.fx() as f32, intr.fy() as f32],
                    [intr.width_px as f32, intr.height_px as f32],
                )
                .with_camera_xyz(rerun::components::ViewCoordinates::FLU)
                .with_image_plane_distance((0.1 * unit) as f32),
            )?;
        }
        for (body, at) in scene.bodies.iter().zip(&placements) {
            let path = if body.robot_link {
                format!("world/robot/{}", body.name)
            } else {
                format!("world/{}", body.name)
            };
            if !body.robot_link {
                self.rec.log(path.as_str(), &transform(at))?;
            }
            for (k, part) in body.parts.iter().enumerate() {
                let c = match part.role {
                    Role::Floor => continue,
                    Role::BeaconPole => GREY,
                    Role::BeaconBand => ORANGE,
                    Role::Robot => BLUE,
                };
                log_shape(&self.rec, &format!("{path}/collider_{k}"), part, colour(c))?;
            }
        }
        // The floor as a grid, the line of approach and the test range's ends.
        let beacon = sim.config().beacon.xy_m;
        let near_m = 1e-3
            * self
                .reference
                .sensor
                .iter()
                .map(|p| p.0)
                .fold(f64::INFINITY, f64::min);
        let (cell, x0, x1) = (
            0.2 * unit,
            beacon[0] - 1.2 * self.far_m,
            beacon[0] + 0.3 * unit,
        );
        let (y0, y1) = (beacon[1] - 0.8 * unit, beacon[1] + 0.8 * unit);
        let mut grid = Vec::new();
        let mut x = x0;
        while x <= x1 {
            grid.push(vec![[x as f32, y0 as f32, 0.0], [x as f32, y1 as f32, 0.0]]);
            x += cell;
        }
        let mut y = y0;
        while y <= y1 + 1e-9 {
            grid.push(vec![[x0 as f32, y as f32, 0.0], [x1 as f32, y as f32, 0.0]]);
            y += cell;
        }
        self.rec.log(
            "world/floor",
            &rerun::LineStrips3D::new(grid)
                .with_colors([colour(LIGHT)])
                .with_radii([(0.002 * unit) as f32]),
        )?;
        let (bx, by) = (beacon[0] as f32, beacon[1] as f32);
        let z = (0.002 * unit) as f32;
        let mut approach = vec![vec![[x0 as f32, by, z], [bx, by, z]]];
        for d in [near_m, self.far_m] {
            let x = bx - d as f32;
            let w = (0.15 * unit) as f32;
            approach.push(vec![[x, by - w, z], [x, by + w, z]]);
        }
        self.rec.log(
            "world/approach",
            &rerun::LineStrips3D::new(approach)
                .with_colors([colour(PALE_BLUE)])
                .with_radii([(0.004 * unit) as f32])
                .with_labels(["line of approach", "near end of the test range", "far end"]),
        )?;
        self.world = Some(*sim.config());
        self.scene = Some(scene);
        Ok(())
    }

    /// Logs what the learner knows after a frame: `x_a`, `x_s` and the
    /// filter's estimate, in mm by the last judged sensor model's gauge.
    pub fn learner_row(&mut self, row: &TraceRow) -> Result<(), RrdError> {
        let Some((scale, offset)) = self.gauge else {
            return Ok(());
        };
        self.rec.set_duration_secs(TIMELINE, row.t_s);
        for (path, value) in [
            ("series/distance/x_a", row.x_a),
            ("series/distance/x_s", row.x_s),
            ("series/distance/filter", row.x_loc),
        ] {
            if let Some(v) = value.map(|v| offset + scale * v).filter(|v| v.is_finite()) {
                self.rec.log(path, &rerun::Scalars::single(v))?;
            }
        }
        Ok(())
    }

    /// Logs a judgement of the learned models: their errors, and the models
    /// against the measured ones (after the metrics' best maps).
    pub fn judgement(&mut self, j: &Judgement) -> Result<(), RrdError> {
        self.rec.set_duration_secs(TIMELINE, j.t_s);
        let world = self.reference.at(j.t_s).clone();
        for (path, value) in [
            ("series/error/action", j.action_rmse_mm_s),
            ("series/error/sensor", j.sensor_rmse_mm),
        ] {
            if let Some(v) = value {
                self.rec.log(path, &rerun::Scalars::single(v))?;
            }
        }
        if let Some(s) = j.sensor_model {
            let fit = metrics::sensor_error(&s, &world.sensor);
            self.gauge = Some((fit.scale, fit.offset)).filter(|g| g.0.is_finite() && g.0 != 0.0);
        }
        self.models(&world, j.action_model, j.sensor_model)?;
        Ok(())
    }

    /// The models against the measured ones, drawn as the run's report draws
    /// them (Fig. 7a and 7b).
    fn models(
        &self,
        world: &Reference,
        action: Option<scasm::Polynomial>,
        sensor: Option<scasm::Polynomial>,
    ) -> Result<(), RrdError> {
        let charts = [
            (
                "models/action",
                action_chart(
                    "action model: learned (best scale) and measured",
                    &world.action,
                    None,
                    action,
                ),
            ),
            (
                "models/sensor",
                sensor_chart(
                    "sensor model: learned (best affine map) and measured",
                    &world.sensor,
                    sensor,
                ),
            ),
        ];
        for (path, chart) in charts {
            self.rec.log(
                path,
                &rerun::EncodedImage::from_file_contents(chart.png()?)
                    .with_media_type(rerun::MediaType::png()),
            )?;
        }
        Ok(())
    }

    /// Writes out everything logged.
    pub fn finish(self) -> Result<(), RrdError> {
        self.rec
            .flush_blocking()
            .map_err(|e| RrdError::Flush(e.to_string()))
    }
}

/// Writes the trial of `scenario` from `seed`, run by learner `learner`, to
/// `log`, frame by frame: the world, then what the learner knew after it.
/// The learner runs over `recording` (the trial's recording, or, if `None`,
/// one made first); then the physics runs the trial again for the scene
/// (with a behaviour that steers by the learner's models, beside another
/// of the same learner fed the same frames), and each frame is checked
/// against the recording's, bit for bit.
pub fn log_trial(
    log: &mut TrialLog,
    scenario: &Scenario,
    models: &MeasuredModels,
    seed: u64,
    learner: &str,
    recording: Option<&Recording>,
) -> Result<RecordedTrial, RrdError> {
    let recording = match recording {
        Some(r) => r.clone(),
        None => experiment::record_for(scenario, models, seed, learner)?,
    };
    let outcome = experiment::learn_every(scenario, models, &recording, learner, MODELS_EVERY_S)?;
    let config = experiment::trial_config(scenario, models, seed)?;
    let mut runner = TrialRunner::new(&scenario.description, scenario.sim, config)?;
    let mut twin = experiment::steering_twin(scenario, models, learner)?;
    let mut judgements = outcome.over_time.iter().peekable();
    for (k, (recorded, row)) in recording.frames.iter().zip(&outcome.trace).enumerate() {
        let frame = match twin.as_mut() {
            Some(twin) => runner.step_frame_steered(twin.learner.as_mut())?,
            None => runner.step_frame()?,
        };
        if frame != *recorded {
            return Err(RrdError::NotReproduced { seed, frame: k });
        }
        log.world_frame(runner.sim(), &frame)?;
        while let Some(j) = judgements.next_if(|j| j.t_s <= row.t_s) {
            log.judgement(j)?;
        }
        log.learner_row(row)?;
    }
    for j in judgements.chain(std::iter::once(&outcome.last)) {
        log.judgement(j)?;
    }
    Ok((recording, outcome))
}

fn f32s(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

fn quaternion(q: [f64; 4]) -> rerun::Quaternion {
    rerun::Quaternion::from_xyzw(q.map(|x| x as f32))
}

fn transform(at: &Placement) -> rerun::Transform3D {
    rerun::Transform3D::from_translation_rotation(
        f32s(at.translation_m),
        quaternion(at.rotation_xyzw),
    )
}

/// The Hamilton product `a b` of quaternions `[x, y, z, w]`.
fn product(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let ([ax, ay, az, aw], [bx, by, bz, bw]) = (a, b);
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// Logs one collider, in its body's frame.
fn log_shape(
    rec: &RecordingStream,
    path: &str,
    part: &quadsim::scene::Part,
    colour: Color,
) -> Result<(), RrdError> {
    let at = part.in_body;
    let centre = f32s(at.translation_m);
    let solid = rerun::FillMode::Solid;
    match part.shape {
        Shape::Cuboid { half_extents_m } => rec.log(
            path,
            &rerun::Boxes3D::from_centers_and_half_sizes([centre], [f32s(half_extents_m)])
                .with_quaternions([quaternion(at.rotation_xyzw)])
                .with_colors([colour])
                .with_fill_mode(solid),
        )?,
        Shape::Ball { radius_m } => rec.log(
            path,
            &rerun::Ellipsoids3D::from_centers_and_radii([centre], [radius_m as f32])
                .with_colors([colour])
                .with_fill_mode(solid),
        )?,
        Shape::Capsule { a_m, b_m, radius_m } => rec.log(
            path,
            &rerun::Capsules3D::from_endpoints_and_radii(
                [f32s(at.apply(a_m))],
                [f32s(at.apply(b_m))],
                [radius_m as f32],
            )
            .with_colors([colour])
            .with_fill_mode(solid),
        )?,
        Shape::Cylinder {
            half_height_m,
            radius_m,
        } => {
            // Rerun's cylinders stand along z, parry's along y.
            let h = std::f64::consts::FRAC_1_SQRT_2;
            let z_to_y = [-h, 0.0, 0.0, h];
            rec.log(
                path,
                &rerun::Cylinders3D::from_lengths_and_radii(
                    [(2.0 * half_height_m) as f32],
                    [radius_m as f32],
                )
                .with_centers([centre])
                .with_quaternions([quaternion(product(at.rotation_xyzw, z_to_y))])
                .with_colors([colour])
                .with_fill_mode(solid),
            )?
        }
        Shape::Bounds { min_m, max_m } => {
            let mid: [f64; 3] = std::array::from_fn(|i| 0.5 * (min_m[i] + max_m[i]));
            let half: [f64; 3] = std::array::from_fn(|i| 0.5 * (max_m[i] - min_m[i]));
            rec.log(
                path,
                &rerun::Boxes3D::from_centers_and_half_sizes([f32s(at.apply(mid))], [f32s(half)])
                    .with_quaternions([quaternion(at.rotation_xyzw)])
                    .with_colors([colour]),
            )?
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_quarter_turns_make_a_half_turn() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let qz = [0.0, 0.0, h, h];
        let q = product(qz, qz);
        // Two quarter turns about z: a half turn, (0, 0, 1, 0).
        for (a, b) in q.iter().zip([0.0, 0.0, 1.0, 0.0]) {
            assert!((a - b).abs() < 1e-12, "{q:?}");
        }
    }
}
