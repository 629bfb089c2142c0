//! The egui overlay: the frame's statistics in a corner, and a panel whose controls
//! switch structure, layout, policy, integrator, backend, samples, threads, view and
//! time live. The panel only reports what was asked ([`Request`]); the app applies it.

use crate::keys::{self, Command};
use crate::timings::FrameRow;
use crate::views::{Show, MAX_BOX_DEPTH};
use dynray_accel::{AccelKind, SceneLayout, UpdatePolicy};
use dynray_engine::Live;
use dynray_gpu::GpuStrategy;
use dynray_render::IntegratorKind;

/// What the panel asked for this frame.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// Switch the job (structure, layout, integrator, backend, samples …) and policy.
    pub job: Option<(dynray_engine::RenderJob, UpdatePolicy)>,
    /// Keys pressed through buttons.
    pub commands: Vec<Command>,
    /// A new view.
    pub show: Option<Show>,
    /// Scrubbed to this time.
    pub time: Option<f32>,
    /// Threads (`None`: every core).
    pub threads: Option<Option<usize>>,
    /// Automatic resolution scaling on or off.
    pub auto_scale: Option<bool>,
    /// The resolution scale while automatic scaling is off.
    pub scale: Option<f32>,
    /// A mistake to show (a structure text that does not parse).
    pub error: Option<String>,
}

/// What the panel shows that the app keeps.
pub struct PanelState<'a> {
    /// The live job.
    pub live: &'a Live,
    /// The last frames' figures (the last is this frame's).
    pub rows: &'a [FrameRow],
    /// Frames per second over the last second.
    pub fps: f64,
    /// The current view.
    pub show: Show,
    /// Playing.
    pub playing: bool,
    /// Automatic resolution scaling.
    pub auto_scale: bool,
    /// The scale while it is off.
    pub fixed_scale: f32,
    /// The latest message (saved files, errors of a switch).
    pub status: &'a str,
    /// The adapter presenting.
    pub adapter: &'a str,
    /// Memory the structure holds, bytes.
    pub structure_bytes: usize,
}

/// Draws the overlay and returns what was asked. `accel_text` is the structure field's
/// text, kept by the caller between frames while it is edited.
pub fn draw(ctx: &egui::Context, accel_text: &mut String, s: &PanelState<'_>) -> Request {
    let mut req = Request::default();
    stats(ctx, s);
    egui::Window::new("dynray").anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0]).default_open(false).resizable(false).show(
        ctx,
        |ui| {
            structure(ui, s, accel_text, &mut req);
            ui.separator();
            image(ui, s, &mut req);
            ui.separator();
            time(ui, s, &mut req);
            ui.separator();
            camera(ui, s, &mut req);
            ui.collapsing("keys", |ui| {
                egui::Grid::new("keys").show(ui, |ui| {
                    for (name, what) in keys::help() {
                        ui.monospace(name);
                        ui.label(what);
                        ui.end_row();
                    }
                    ui.monospace("drag");
                    ui.label("orbit (right button or shift: pan)");
                    ui.end_row();
                    ui.monospace("wheel");
                    ui.label("zoom");
                    ui.end_row();
                });
            });
        },
    );
    req
}

/// The corner: fps, the frame's split, rays/s, samples, memory.
fn stats(ctx: &egui::Context, s: &PanelState<'_>) {
    let Some(row) = s.rows.last() else { return };
    egui::Area::new(egui::Id::unique("dynray stats")).fixed_pos([8.0, 8.0]).show(ctx, |ui| {
        egui::Frame::popup(ui.style()).show(ui, |ui| {
            let live = s.live;
            ui.monospace(format!(
                "{:.1} fps  {}x{} ({:.0} %)  {} / {} spp{}",
                s.fps,
                row.width,
                row.height,
                live.scale() * 100.0,
                row.samples,
                live.spp(),
                if live.converged() { "  done" } else { "" }
            ));
            ui.monospace(format!(
                "pose {:.1} (physics {:.1})  update {:.1}{}  trace {:.1}  view {:.1}  present {:.1} ms",
                row.pose_ms,
                row.physics_ms,
                row.update_ms,
                if row.update.is_empty() { String::new() } else { format!(" {}", row.update) },
                row.render_ms,
                row.view_ms,
                row.present_ms
            ));
            let mrays = if row.render_ms > 0.0 { row.rays as f64 / row.render_ms / 1e3 } else { 0.0 };
            ui.monospace(format!(
                "{:.2} Mrays/s  {}  structure {:.1} MiB  t = {:.3} s",
                mrays,
                live.tracer().describe(),
                s.structure_bytes as f64 / (1 << 20) as f64,
                live.time()
            ));
            ui.monospace(format!("{}  {}  presenting on {}", live.job().integrator, s.show, s.adapter));
            if !s.status.is_empty() {
                ui.label(s.status);
            }
        });
    });
}

fn structure(ui: &mut egui::Ui, s: &PanelState<'_>, accel_text: &mut String, req: &mut Request) {
    let job = s.live.job();
    let mut next = job.clone();
    let mut policy = s.live.policy();
    egui::Grid::new("structure").show(ui, |ui| {
        ui.label("structure");
        ui.horizontal(|ui| {
            egui::ComboBox::from_id_salt("accel").selected_text(next.accel.kind.name()).show_ui(ui, |ui| {
                for k in AccelKind::ALL {
                    if ui.selectable_label(next.accel.kind == *k, k.name()).clicked() {
                        next.accel = dynray_accel::AccelSpec::new(*k);
                    }
                }
            });
            // Any `--accel` text, parameters included, applied on Enter.
            let edit = ui.add(egui::TextEdit::singleline(accel_text).desired_width(160.0).hint_text("bih:max_prims=5"));
            if edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                match accel_text.parse::<dynray_accel::AccelSpec>() {
                    Ok(spec) => next.accel = spec,
                    Err(e) => req.error = Some(e.to_string()),
                }
            }
        });
        ui.end_row();
        ui.label("layout");
        egui::ComboBox::from_id_salt("layout").selected_text(next.scene_accel.to_string()).show_ui(ui, |ui| {
            for name in SceneLayout::NAMES {
                let l: SceneLayout = name.parse().expect("listed names parse");
                ui.selectable_value(&mut next.scene_accel, l, name);
            }
        });
        ui.end_row();
        ui.label("update");
        egui::ComboBox::from_id_salt("policy").selected_text(policy.to_string()).show_ui(ui, |ui| {
            for p in [UpdatePolicy::default(), UpdatePolicy::Refit, UpdatePolicy::Rebuild] {
                ui.selectable_value(&mut policy, p, p.to_string());
            }
        });
        ui.end_row();
        ui.label("backend");
        let mut gpu = next.backend.is_gpu();
        ui.horizontal(|ui| {
            ui.radio_value(&mut gpu, false, "CPU");
            ui.radio_value(&mut gpu, true, "GPU");
        });
        if gpu != next.backend.is_gpu() {
            next.backend.gpu = gpu.then(Default::default);
            if gpu {
                next.accel = "bvh2".parse().expect("bvh2 parses");
            }
        }
        ui.end_row();
        if gpu {
            ui.label("strategy");
            egui::ComboBox::from_id_salt("strategy").selected_text(next.gpu_strategy.to_string()).show_ui(ui, |ui| {
                for name in GpuStrategy::NAMES {
                    let st: GpuStrategy = name.parse().expect("listed names parse");
                    ui.selectable_value(&mut next.gpu_strategy, st, name);
                }
            });
            ui.end_row();
        }
    });
    if next.gpu_strategy != GpuStrategy::Wavefront && next.integrator != IntegratorKind::Whitted {
        next.integrator = IntegratorKind::Whitted;
    }
    if !same(&next, job) || policy != s.live.policy() {
        req.job = Some((next, policy));
    }
}

fn image(ui: &mut egui::Ui, s: &PanelState<'_>, req: &mut Request) {
    let job = s.live.job();
    let mut next = job.clone();
    egui::Grid::new("image").show(ui, |ui| {
        ui.label("integrator");
        ui.horizontal(|ui| {
            for k in [IntegratorKind::Whitted, IntegratorKind::Cumulative, IntegratorKind::Path] {
                ui.radio_value(&mut next.integrator, k, k.to_string());
            }
        });
        ui.end_row();
        ui.label("spp");
        let mut spp = s.live.spp();
        if ui.add(egui::DragValue::new(&mut spp).range(1..=4096)).changed() {
            next.spp = Some(spp);
        }
        ui.end_row();
        ui.label("threads");
        let mut threads = s.live.threads();
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get()).max(threads);
        if ui.add(egui::Slider::new(&mut threads, 1..=cores)).changed() {
            req.threads = Some(Some(threads));
        }
        ui.end_row();
        ui.label("resolution");
        let mut auto = s.auto_scale;
        ui.horizontal(|ui| {
            if ui.checkbox(&mut auto, "scale down while moving").changed() {
                req.auto_scale = Some(auto);
            }
            if !s.auto_scale {
                let mut scale = s.fixed_scale;
                if ui.add(egui::Slider::new(&mut scale, 0.125..=1.0).text("scale")).changed() {
                    req.scale = Some(scale);
                }
            }
        });
        ui.end_row();
        ui.label("view");
        ui.horizontal(|ui| {
            let mut show = s.show;
            ui.radio_value(&mut show, Show::Image, "image");
            ui.radio_value(&mut show, Show::Heatmap, "heat map");
            let depth = match show {
                Show::Boxes(d) => d,
                _ => crate::views::DEFAULT_BOX_DEPTH,
            };
            ui.radio_value(&mut show, Show::Boxes(depth), "boxes");
            if let Show::Boxes(mut d) = show {
                ui.add(egui::DragValue::new(&mut d).range(0..=MAX_BOX_DEPTH).prefix("depth "));
                show = Show::Boxes(d);
            }
            if show != s.show {
                req.show = Some(show);
            }
        });
        ui.end_row();
    });
    ui.horizontal(|ui| {
        if ui.button("save PNG").clicked() {
            req.commands.push(Command::SavePng);
        }
        if ui.button("save EXR").clicked() {
            req.commands.push(Command::SaveExr);
        }
        if ui.button("write timings").clicked() {
            req.commands.push(Command::WriteTimings);
        }
    });
    if next.integrator != job.integrator && next.backend.is_gpu() && next.integrator != IntegratorKind::Whitted {
        // The GPU's cumulative and path kernels are the wavefront strategy's modes.
        next.gpu_strategy = GpuStrategy::Wavefront;
    }
    if !same(&next, job) && req.job.is_none() {
        req.job = Some((next, s.live.policy()));
    }
}

fn time(ui: &mut egui::Ui, s: &PanelState<'_>, req: &mut Request) {
    let tl = s.live.timeline();
    let (start, end) = (tl.time_of(0), tl.time_of(tl.frames.saturating_sub(1)));
    ui.horizontal(|ui| {
        if ui.button(if s.playing { "pause" } else { "play" }).clicked() {
            req.commands.push(Command::TogglePlay);
        }
        if ui.button("<").clicked() {
            req.commands.push(Command::StepBack);
        }
        if ui.button(">").clicked() {
            req.commands.push(Command::StepForward);
        }
        let mut t = s.live.time();
        if end > start && ui.add(egui::Slider::new(&mut t, start..=end).suffix(" s")).changed() {
            req.time = Some(t);
        }
    });
}

fn camera(ui: &mut egui::Ui, s: &PanelState<'_>, req: &mut Request) {
    let text = dynray_engine::camera_text(&s.live.camera());
    ui.label("camera (for --camera or a .scn `camera { … }`):");
    ui.add(egui::Label::new(egui::RichText::new(&text).monospace()).wrap());
    ui.horizontal(|ui| {
        if ui.button("copy").clicked() {
            ui.ctx().copy_text(text.clone());
        }
        if ui.button("reset").clicked() {
            req.commands.push(Command::ResetCamera);
        }
    });
}

/// Two jobs that render the same (RenderJob has no PartialEq: its GPU options and time
/// choice are compared field by field where the panel changes them).
fn same(a: &dynray_engine::RenderJob, b: &dynray_engine::RenderJob) -> bool {
    a.accel == b.accel
        && a.scene_accel == b.scene_accel
        && a.integrator == b.integrator
        && a.spp == b.spp
        && a.backend.gpu == b.backend.gpu
        && a.gpu_strategy == b.gpu_strategy
}
