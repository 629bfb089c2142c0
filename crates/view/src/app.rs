//! The window and its frame. Each frame: the script's and the user's input move the
//! camera, time and switches; the live job steps (pose → physics → update → one
//! progressive frame); the view (image, heat map or boxes) becomes RGBA; the panel is
//! drawn; everything is presented; the frame's split goes into the timings.

use crate::keys::Command;
use crate::navigate;
use crate::panel::{self, PanelState, Request};
use crate::present::{PanelPaint, Presenter};
use crate::script::{Event, Script};
use crate::timings::{self, FrameRow};
use crate::views::{self, Show, MAX_BOX_DEPTH};
use anyhow::{bail, Context, Result};
use dynray_accel::{UpdateAction, UpdatePolicy};
use dynray_engine::{Live, LiveFrame, Loaded, RenderJob};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::ModifiersState;
use winit::window::{Window, WindowId};

/// Everything `dynray view` is asked.
#[derive(Clone, Debug, Default)]
pub struct ViewOptions {
    /// The scene, mesh or field file; `None`: the built-in demo.
    pub scene: Option<PathBuf>,
    /// The render job the image follows (size, structure, integrator, backend …).
    pub job: RenderJob,
    /// The structures' update policy.
    pub policy: UpdatePolicy,
    /// Render threads (`None`: every core).
    pub threads: Option<usize>,
    /// Start playing the animation.
    pub play: bool,
    /// The starting view.
    pub show: Option<Show>,
    /// Scripted input.
    pub script: Option<PathBuf>,
    /// Close after this many frames.
    pub exit_after: Option<u64>,
    /// Write the window's content here when it closes (PNG).
    pub screenshot: Option<PathBuf>,
    /// No panel or statistics over the image.
    pub no_overlay: bool,
    /// Write one row per frame here when it closes (CSV).
    pub timings: Option<PathBuf>,
    /// Record every frame the window shows into this GIF, written when it closes.
    pub record: Option<PathBuf>,
    /// A fixed resolution scale in (0, 1] instead of the automatic one.
    pub scale: Option<f32>,
}

/// A frame that takes longer than this while the view moves halves the resolution.
const SLOW_FRAME: Duration = Duration::from_millis(100);
/// A frame faster than this while moving doubles it back (towards full size).
const FAST_FRAME: Duration = Duration::from_millis(30);
/// Smallest resolution scale.
const MIN_SCALE: f32 = 1.0 / 8.0;

/// Opens the window and runs until it is closed, `--exit-after` frames pass, or an error.
pub fn run(options: ViewOptions) -> Result<()> {
    check_outputs(&options)?;
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        bail!(
            "no display: `dynray view` opens a window and neither DISPLAY nor WAYLAND_DISPLAY is set \
             (on a machine without a screen, run it under `xvfb-run`, or render files with `dynray render`)"
        );
    }
    let script = options.script.as_deref().map(Script::load).transpose()?;
    let loaded = Loaded::open(options.scene.as_deref())?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let mut live = Live::new(loaded, options.job.clone(), options.policy)?;
    live.set_threads(options.threads)?;
    let event_loop = EventLoop::new().map_err(|e| anyhow::anyhow!("cannot open a window: {e}"))?;
    let mut app = App::new(options, live, script);
    event_loop.run_app(&mut app).map_err(|e| anyhow::anyhow!("the window's event loop failed: {e}"))?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Outputs must be PNG/CSV and never the scene read.
fn check_outputs(options: &ViewOptions) -> Result<()> {
    if let Some(p) = &options.screenshot {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            bail!("{}: --screenshot writes a PNG (use a .png name)", p.display());
        }
    }
    if let Some(p) = &options.timings {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
            bail!("{}: --timings writes CSV (use a .csv name)", p.display());
        }
    }
    if let Some(s) = options.scale {
        if !(s > 0.0 && s <= 1.0) {
            bail!("--scale must be in (0, 1], got {s}");
        }
    }
    if let Some(p) = &options.record {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("gif")) {
            bail!("{}: --record writes an animated GIF (use a .gif name)", p.display());
        }
    }
    if let Some(scene) = &options.scene {
        for out in [&options.screenshot, &options.timings, &options.record].into_iter().flatten() {
            if same_file(scene, out) {
                bail!("{}: is the scene being viewed; it is never overwritten", out.display());
            }
        }
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Mouse drags in progress.
#[derive(Clone, Copy, Debug, Default)]
struct Pointer {
    at: Option<(f32, f32)>,
    orbiting: bool,
    panning: bool,
}

struct App {
    options: ViewOptions,
    live: Live,
    script: Option<Script>,
    window: Option<Arc<Window>>,
    presenter: Option<Presenter>,
    egui: egui::Context,
    egui_state: Option<egui_winit::State>,
    show: Show,
    overlay: bool,
    playing: bool,
    auto_scale: bool,
    /// The resolution scale while automatic scaling is off.
    fixed_scale: f32,
    /// The panel's structure text (`bih:max_prims=5`), edited until Enter.
    accel_text: String,
    pointer: Pointer,
    modifiers: ModifiersState,
    /// The camera moved since the last frame.
    moved: bool,
    last_frame: Option<Instant>,
    frame_times: Vec<Instant>,
    rows: Vec<FrameRow>,
    frames: u64,
    status: String,
    /// The heat map of the last restart, recomputed on change.
    view_cache: Option<Vec<u8>>,
    saved: u32,
    recording: Option<crate::record::Recording>,
    error: Option<anyhow::Error>,
    exiting: bool,
}

impl App {
    fn new(options: ViewOptions, live: Live, script: Option<Script>) -> Self {
        let recording = options.record.as_ref().map(|_| crate::record::Recording::default());
        App {
            show: options.show.unwrap_or(Show::Image),
            overlay: !options.no_overlay,
            playing: options.play,
            auto_scale: options.scale.is_none(),
            fixed_scale: options.scale.unwrap_or(1.0),
            accel_text: live.job().accel.to_string(),
            options,
            live,
            script,
            window: None,
            presenter: None,
            egui: egui::Context::default(),
            egui_state: None,
            pointer: Pointer::default(),
            modifiers: ModifiersState::empty(),
            moved: false,
            last_frame: None,
            frame_times: Vec::new(),
            rows: Vec::new(),
            frames: 0,
            status: String::new(),
            view_cache: None,
            saved: 0,
            recording,
            error: None,
            exiting: false,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error.get_or_insert(e);
        self.exiting = true;
        event_loop.exit();
    }

    /// Applies a key's command.
    fn command(&mut self, c: Command, event_loop: &ActiveEventLoop) {
        let tl = self.live.timeline();
        let frame_time = 1.0 / tl.frame_rate.max(1e-3);
        match c {
            Command::TogglePlay => self.playing = !self.playing,
            Command::StepForward | Command::StepBack => {
                self.playing = false;
                let dir = if c == Command::StepForward { 1.0 } else { -1.0 };
                self.live.set_time(self.live.time() + dir * frame_time);
            }
            Command::ResetCamera => {
                self.live.reset_camera();
                self.moved = true;
            }
            Command::Fly(f, r, u) => {
                let step = self.scene_size() * 0.02;
                self.live.set_camera(navigate::fly(&self.live.camera(), (f, r, u), step));
                self.moved = true;
            }
            Command::ShowImage => self.set_show(Show::Image),
            Command::ShowHeatmap => self.set_show(Show::Heatmap),
            Command::ShowBoxes => {
                let d = match self.show {
                    Show::Boxes(d) => d,
                    _ => views::DEFAULT_BOX_DEPTH,
                };
                self.set_show(Show::Boxes(d))
            }
            Command::BoxDepth(delta) => {
                if let Show::Boxes(d) = self.show {
                    self.set_show(Show::Boxes(d.saturating_add_signed(delta as i32).min(MAX_BOX_DEPTH)));
                }
            }
            Command::SavePng | Command::SaveExr => {
                let ext = if c == Command::SavePng { "png" } else { "exr" };
                self.status = match self.save(ext) {
                    Ok(p) => format!("saved {}", p.display()),
                    Err(e) => format!("{e:#}"),
                };
            }
            Command::WriteTimings => {
                let path = self.options.timings.clone().unwrap_or_else(|| PathBuf::from("dynray-view-timings.csv"));
                self.status = match timings::write(&path, &self.rows) {
                    Ok(()) => format!("wrote {} frames to {}", self.rows.len(), path.display()),
                    Err(e) => format!("{e:#}"),
                };
            }
            Command::NextStructure => {
                let job = self.live.job();
                let all = dynray_accel::AccelKind::ALL;
                let at = all.iter().position(|k| *k == job.accel.kind).unwrap_or(0);
                // The GPU traces the binary BVH only; brute force is for checking, not viewing.
                let next = (1..=all.len())
                    .map(|i| all[(at + i) % all.len()])
                    .find(|k| *k != dynray_accel::AccelKind::Brute)
                    .expect("kinds besides brute");
                if job.backend.is_gpu() {
                    self.status = "the GPU backend traces bvh2 only".to_string();
                } else {
                    let job = RenderJob { accel: dynray_accel::AccelSpec::new(next), ..job.clone() };
                    self.status = match self.live.reconfigure(job, self.live.policy()) {
                        Ok(()) => format!("structure: {}", next.name()),
                        Err(e) => format!("{e:#}"),
                    };
                    self.view_cache = None;
                }
            }
            Command::ToggleOverlay => self.overlay = !self.overlay,
            Command::Quit => {
                self.exiting = true;
                event_loop.exit();
            }
        }
    }

    fn set_show(&mut self, show: Show) {
        self.show = show;
        self.view_cache = None;
    }

    /// The size of the scene: the diagonal of its bounds (flying steps scale with it).
    fn scene_size(&self) -> f32 {
        let d = self.live.frame().mesh.bounds().extent().length();
        if d.is_finite() && d > 0.0 {
            d
        } else {
            1.0
        }
    }

    /// Saves the image (not the overlays) under the next free `dynray-view-NNNN.EXT`.
    fn save(&mut self, ext: &str) -> Result<PathBuf> {
        let path = loop {
            self.saved += 1;
            let p = PathBuf::from(format!("dynray-view-{:04}.{ext}", self.saved));
            if !p.exists() {
                break p;
            }
        };
        dynray_render::write_image(&self.live.image_film()?, &path)?;
        Ok(path)
    }

    /// The script's events of this frame.
    fn play_script(&mut self, event_loop: &ActiveEventLoop) {
        let Some(script) = self.script.as_mut() else { return };
        for e in script.frame_events() {
            match e {
                Event::Wait(_) => {}
                Event::Key(name) => {
                    if let Some(c) = Command::of_key(&name) {
                        self.command(c, event_loop);
                    }
                }
                Event::Drag { from, to } => {
                    let cam = navigate::orbit(&self.live.camera(), to.0 - from.0, to.1 - from.1);
                    self.live.set_camera(cam);
                    self.moved = true;
                }
                Event::Scroll(n) => {
                    self.live.set_camera(navigate::zoom(&self.live.camera(), n));
                    self.moved = true;
                }
            }
        }
    }

    /// Advances time while playing (wall time; looping over the timeline).
    fn advance_time(&mut self, now: Instant) {
        let dt = self.last_frame.map_or(0.0, |t| now.duration_since(t).as_secs_f32());
        if !self.playing || dt <= 0.0 {
            return;
        }
        let tl = self.live.timeline();
        let (start, end) = (tl.time_of(0), tl.time_of(tl.frames.saturating_sub(1)));
        // At most two timeline frames per shown frame: where a frame (physics above all)
        // takes longer than that, playback slows down instead of spiralling, each frame
        // owing the simulation more steps than the last.
        let dt = dt.min(2.0 / tl.frame_rate.max(1e-3));
        let mut t = self.live.time() + dt;
        if end > start && t > end {
            t = start + (t - end) % (end - start);
        }
        self.live.set_time(t);
    }

    /// Resolution scaling: smaller while moving and slow, full size when still.
    fn choose_scale(&mut self) {
        let moving = self.moved || self.playing;
        let last = self.rows.last().map(|r| Duration::from_secs_f64(r.render_ms / 1e3));
        let scale = if !self.auto_scale {
            self.fixed_scale
        } else if !moving {
            1.0
        } else {
            match last {
                Some(d) if d > SLOW_FRAME => (self.live.scale() * 0.5).max(MIN_SCALE),
                Some(d) if d < FAST_FRAME => (self.live.scale() * 2.0).min(1.0),
                _ => self.live.scale(),
            }
        };
        self.live.set_scale(scale);
    }

    /// The RGBA pixels of the current view, and the time the view's extra work took.
    fn view_pixels(&mut self, report: &LiveFrame) -> (Vec<u8>, u32, u32, Duration) {
        let (w, h) = (self.live.film().width(), self.live.film().height());
        let t0 = Instant::now();
        if report.restarted {
            self.view_cache = None;
        }
        if self.show != Show::Image {
            if let Err(e) = self.live.build_view_structure() {
                self.status = format!("{e:#}");
            }
        }
        let image = |live: &Live| to_rgba(&live.film().to_srgb8());
        let rgba = match (self.show, self.live.view_structure()) {
            (Show::Heatmap, Some(accel)) => {
                // Primary rays only: the same until the view restarts.
                let frame = self.live.frame();
                self.view_cache.get_or_insert_with(|| views::heatmap(frame, accel).0).clone()
            }
            (Show::Boxes(depth), Some(accel)) => {
                let mut rgba = image(&self.live);
                let mut boxes = Vec::new();
                accel.outline(depth, &mut boxes);
                views::draw_boxes(&mut rgba, (w, h), self.live.frame(), &boxes);
                rgba
            }
            _ => image(&self.live),
        };
        (rgba, w, h, t0.elapsed())
    }

    /// One frame of the viewer.
    fn frame(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let start = Instant::now();
        self.play_script(event_loop);
        self.advance_time(start);
        self.choose_scale();
        self.moved = false;
        let shared = self.presenter.as_ref().is_some_and(|p| p.shared_context().is_some());
        self.live.present_on_device(shared && self.show == Show::Image);
        let report = self.live.step()?;
        let (rgba, w, h, view_time) = match self.live.device_image() {
            // The GPU backend's image, resolved on the window's device: nothing to upload.
            Some(image) => (Vec::new(), image.width(), image.height(), Duration::ZERO),
            None => self.view_pixels(&report),
        };

        // This frame's row first, so the panel shows it (present and total follow below).
        self.rows.push(FrameRow {
            frame: self.frames,
            time: self.live.time(),
            samples: report.samples,
            width: w,
            height: h,
            pose_ms: ms(report.pose),
            physics_ms: ms(report.physics),
            update_ms: report.update.map_or(0.0, |u| ms(u.time)),
            update: report.update.map_or(String::new(), |u| action(u.action).to_string()),
            render_ms: ms(report.render),
            view_ms: ms(view_time),
            present_ms: 0.0,
            total_ms: 0.0,
            rays: report.rays,
            image: if self.live.device_image().is_some() { "device" } else { "host" },
        });
        let t_present = Instant::now();
        let window = self.window.clone().expect("a window before frames");
        let presenter = self.presenter.as_mut().expect("a presenter before frames");
        match self.live.device_image() {
            Some(image) => presenter.show_device_image(image),
            None => presenter.upload(&rgba, w, h),
        }
        let last = self.frames + 1 == self.options.exit_after.unwrap_or(u64::MAX) || self.exiting;
        let capture = (last && self.options.screenshot.is_some()) || self.recording.is_some();
        let mut request = Request::default();
        let shot = if self.overlay {
            let state = self.egui_state.as_mut().expect("made with the window");
            let input = state.take_egui_input(&window);
            let fps = fps(&mut self.frame_times, start);
            let adapter = presenter.adapter().to_string();
            let structure_bytes = self.live.accel().map_or(0, |a| a.memory_bytes());
            let accel_text = &mut self.accel_text;
            let out = self.egui.run_ui(input, |ui| {
                let ctx = ui.ctx().clone();
                request = panel::draw(
                    &ctx,
                    accel_text,
                    &PanelState {
                        live: &self.live,
                        rows: &self.rows,
                        fps,
                        show: self.show,
                        playing: self.playing,
                        auto_scale: self.auto_scale,
                        fixed_scale: self.fixed_scale,
                        status: &self.status,
                        adapter: &adapter,
                        structure_bytes,
                    },
                );
            });
            state.handle_platform_output(&window, out.platform_output);
            let primitives = self.egui.tessellate(out.shapes, out.pixels_per_point);
            let mut textures = out.textures_delta;
            let paint =
                PanelPaint { primitives: &primitives, textures: &textures, pixels_per_point: out.pixels_per_point };
            let shot = presenter.present(Some(paint), capture);
            // Applied above (or lost with the device on an error): egui insists on being told.
            textures.clear();
            shot?
        } else {
            fps(&mut self.frame_times, start);
            presenter.present(None, capture)?
        };
        let present = t_present.elapsed();
        self.apply(request, event_loop);
        if let Some(row) = self.rows.last_mut() {
            row.present_ms = ms(present);
            row.total_ms = ms(start.elapsed());
        }

        self.frames += 1;
        self.last_frame = Some(start);
        if let (Some(rec), Some(shot)) = (self.recording.as_mut(), &shot) {
            rec.push(shot.clone(), self.rows.last().map_or(0.0, |r| r.total_ms));
        }
        if let (Some(shot), Some(path)) = (shot.filter(|_| last), &self.options.screenshot) {
            write_png(path, &shot)?;
        }
        if last {
            self.exiting = true;
            event_loop.exit();
        }
        Ok(())
    }

    /// Applies what the panel asked.
    fn apply(&mut self, r: Request, event_loop: &ActiveEventLoop) {
        if let Some(e) = r.error {
            self.status = e;
        }
        if let Some((job, policy)) = r.job {
            if let Err(e) = self.live.reconfigure(job, policy) {
                self.status = format!("{e:#}");
            } else {
                self.status.clear();
                self.view_cache = None;
            }
        }
        for c in r.commands {
            self.command(c, event_loop);
        }
        if let Some(show) = r.show {
            self.set_show(show);
        }
        if let Some(t) = r.time {
            self.playing = false;
            self.live.set_time(t);
        }
        if let Some(threads) = r.threads {
            if let Err(e) = self.live.set_threads(threads) {
                self.status = format!("{e:#}");
            }
        }
        if let Some(a) = r.auto_scale {
            self.auto_scale = a;
        }
        if let Some(scale) = r.scale {
            self.fixed_scale = scale;
        }
        // The text follows the structure unless it is being edited.
        if !self.egui.egui_wants_keyboard_input() {
            self.accel_text = self.live.job().accel.to_string();
        }
    }

    /// Whether another frame should follow at once.
    fn busy(&self) -> bool {
        !self.live.converged()
            || self.playing
            || self.script.as_ref().is_some_and(|s| !s.finished())
            || self.options.exit_after.is_some()
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, event: &WindowEvent) {
        match event {
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if let Some(c) = Command::of_winit(&event.logical_key) {
                    self.command(c, event_loop);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let down = *state == ElementState::Pressed;
                match button {
                    MouseButton::Left if self.modifiers.shift_key() => self.pointer.panning = down,
                    MouseButton::Left => self.pointer.orbiting = down,
                    MouseButton::Right | MouseButton::Middle => self.pointer.panning = down,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let at = (position.x as f32, position.y as f32);
                if let Some(prev) = self.pointer.at {
                    let (dx, dy) = (at.0 - prev.0, at.1 - prev.1);
                    let cam = self.live.camera();
                    if self.pointer.orbiting {
                        self.live.set_camera(navigate::orbit(&cam, dx, dy));
                        self.moved = true;
                    } else if self.pointer.panning {
                        let height = self.window.as_ref().map_or(1.0, |w| w.inner_size().height as f32);
                        self.live.set_camera(navigate::pan(&cam, dx, dy, height));
                        self.moved = true;
                    }
                }
                self.pointer.at = Some(at);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.live.set_camera(navigate::zoom(&self.live.camera(), notches));
                self.moved = true;
            }
            _ => {}
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = (self.live.frame().settings.width.max(1), self.live.frame().settings.height.max(1));
        let title = format!("dynray view — {}", self.live.label());
        let attrs = Window::default_attributes().with_title(title).with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(event_loop, anyhow::anyhow!("cannot open a window: {e}")),
        };
        let gpu = self.live.job().backend.gpu.clone().unwrap_or_default();
        let presenter = match Presenter::new(window.clone(), event_loop.owned_display_handle(), &gpu) {
            Ok(p) => p,
            Err(e) => return self.fail(event_loop, e),
        };
        // The GPU backend traces on the window's device, so its image stays there.
        if let Some(ctx) = presenter.shared_context() {
            if let Err(e) = self.live.share_gpu(ctx.clone()) {
                return self.fail(event_loop, e);
            }
        }
        self.egui_state = Some(egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        ));
        self.presenter = Some(presenter);
        window.request_redraw();
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let consumed = match (&mut self.egui_state, &self.window) {
            (Some(state), Some(window)) if self.overlay => state.on_window_event(window, &event).consumed,
            _ => false,
        };
        match &event {
            WindowEvent::CloseRequested => {
                self.exiting = true;
                event_loop.exit();
            }
            WindowEvent::Resized(size) => {
                if let Some(p) = self.presenter.as_mut() {
                    p.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested => {
                if self.exiting {
                    return;
                }
                if let Err(e) = self.frame(event_loop) {
                    return self.fail(event_loop, e);
                }
                if self.busy() && !self.exiting {
                    if let Some(w) = &self.window {
                        w.request_redraw();
                    }
                }
            }
            _ if !consumed => {
                self.window_event(event_loop, &event);
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
            }
            _ => {
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        event_loop.set_control_flow(ControlFlow::Wait);
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(path) = self.options.timings.clone() {
            if let Err(e) = timings::write(&path, &self.rows) {
                self.error.get_or_insert(e);
            }
        }
        if let (Some(rec), Some(path)) = (&self.recording, &self.options.record) {
            if rec.dropped() > 0 {
                eprintln!(
                    "dynray: warning: {}: recorded the first {} frames, {} more were not kept",
                    path.display(),
                    rec.len(),
                    rec.dropped()
                );
            }
            if let Err(e) = rec.write(path) {
                self.error.get_or_insert(e);
            }
        }
    }
}

/// Frames per second over the last second, counting the frame starting at `now`.
fn fps(times: &mut Vec<Instant>, now: Instant) -> f64 {
    times.push(now);
    times.retain(|t| now.duration_since(*t) <= Duration::from_secs(1));
    match (times.first(), times.len()) {
        (Some(first), n) if n > 1 => (n - 1) as f64 / now.duration_since(*first).as_secs_f64().max(1e-9),
        _ => 0.0,
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn action(a: UpdateAction) -> &'static str {
    match a {
        UpdateAction::Rebuilt => "rebuild",
        _ => "refit",
    }
}

/// RGB bytes to RGBA (opaque).
fn to_rgba(rgb: &[u8]) -> Vec<u8> {
    rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect()
}

/// Writes `image` as PNG under a temporary name in the same folder, then renames it.
fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .with_context(|| format!("{}: cannot encode", path.display()))?;
    dynray_engine::output::write_atomic(path, &bytes)
}
