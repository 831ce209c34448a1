//! The window: winit events, a rendering thread, softbuffer presentation.
//!
//! The event loop waits (`ControlFlow::Wait`) unless a movement key is held. The
//! rendering thread owns the [`Engine`]; it sleeps on a condition variable while the
//! image is converged and nothing changed, and after each pass it leaves the newest frame
//! in a shared slot and wakes the event loop through its proxy. So an idle viewer uses no
//! CPU, and a slow frame never queues up behind newer input.

use super::camera::FlyCamera;
use super::engine::{pack_rgb, Engine, PassStats};
use super::knobs::{self, Knobs};
use super::script::Step;
use super::{save_png, Bench, Setup};
use std::collections::HashSet;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tracer::image::Image;
use tracer::scene::desc::CameraDesc;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, EventLoopProxy};
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::{Window, WindowId};

/// A finished pass, as the rendering thread hands it over.
struct Frame {
    image: Image,
    stats: PassStats,
    passes: u32,
    target: u32,
    generation: u64,
    /// When the view that this frame shows was requested.
    requested: Instant,
}

#[derive(Default)]
struct State {
    view: Option<(CameraDesc, Knobs)>,
    generation: u64,
    requested: Option<Instant>,
    quit: bool,
    frame: Option<Frame>,
    error: Option<String>,
}

#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    wake: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The rendering thread: renders the newest view, one pass at a time, until converged.
fn render_loop(mut engine: Engine, shared: Arc<Shared>, proxy: EventLoopProxy<()>) {
    let mut seen = 0;
    let mut requested = Instant::now();
    loop {
        let view = {
            let mut st = shared.lock();
            loop {
                if st.quit {
                    return;
                }
                if st.generation != seen {
                    seen = st.generation;
                    requested = st.requested.unwrap_or_else(Instant::now);
                    break st.view.clone();
                }
                if !engine.converged() {
                    break None;
                }
                st = shared.wake.wait(st).unwrap_or_else(|e| e.into_inner());
            }
        };
        let view_changed = view.is_some();
        if let Some((cam, k)) = view {
            if let Err(e) = engine.set_view(&cam, &k) {
                shared.lock().error = Some(e);
            }
        }
        let before = engine.passes();
        let stats = engine.step();
        let frame = Frame {
            image: engine.image(),
            stats,
            passes: engine.passes(),
            target: engine.target_passes(),
            generation: seen,
            requested,
        };
        // A new view is always answered, even if it changed nothing, so the script
        // and the benchmark move on.
        if engine.passes() != before || view_changed {
            shared.lock().frame = Some(frame);
        }
        if proxy.send_event(()).is_err() {
            return;
        }
    }
}

/// What the run does besides showing the scene.
enum Mode {
    Interactive,
    Script { steps: Vec<Step>, next: usize },
    Bench(Bench),
}

struct App {
    shared: Arc<Shared>,
    worker: Option<std::thread::JoinHandle<()>>,
    engine_size: (u32, u32),
    camera: FlyCamera,
    knobs: Knobs,
    selected: usize,
    mode: Mode,
    screenshot: Option<PathBuf>,
    shots: u32,
    scene_name: String,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    pixels: Vec<u32>,
    image: Option<Image>,
    last: Option<(PassStats, u32, u32)>,
    generation: u64,
    held: HashSet<KeyCode>,
    modifiers: ModifiersState,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    tick: Instant,
    error: Option<String>,
    /// The scene's camera (the benchmark's frames start from it).
    home: FlyCamera,
}

/// Opens the window and runs until it is closed (or the script or benchmark ends).
pub(crate) fn run(setup: Setup) -> Result<(), String> {
    let event_loop = EventLoop::<()>::with_user_event()
        .build()
        .map_err(|e| format!("tracer view: cannot open a window: {e}"))?;
    let shared = Arc::new(Shared::default());
    let proxy = event_loop.create_proxy();
    let engine_size = setup.engine.size();
    let knobs = *setup.engine.knobs();
    let worker = {
        let shared = shared.clone();
        let engine = setup.engine;
        std::thread::Builder::new()
            .name("render".into())
            .spawn(move || render_loop(engine, shared, proxy))
            .map_err(|e| format!("tracer view: cannot start the rendering thread: {e}"))?
    };
    let mode = if let Some(frames) = setup.frames {
        Mode::Bench(Bench::new(frames))
    } else if let Some(steps) = setup.script {
        Mode::Script { steps, next: 0 }
    } else {
        Mode::Interactive
    };
    let mut app = App {
        shared,
        worker: Some(worker),
        engine_size,
        camera: setup.camera.clone(),
        knobs,
        selected: 0,
        mode,
        screenshot: setup.screenshot,
        shots: 0,
        scene_name: setup.scene_name,
        window: None,
        surface: None,
        pixels: Vec::new(),
        image: None,
        last: None,
        generation: 0,
        held: HashSet::new(),
        modifiers: ModifiersState::default(),
        drag: None,
        cursor: (0.0, 0.0),
        tick: Instant::now(),
        error: None,
        home: setup.camera.clone(),
    };
    let result = event_loop
        .run_app(&mut app)
        .map_err(|e| format!("tracer view: {e}"));
    app.stop_worker();
    result?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

const MOVE_KEYS: [KeyCode; 10] = [
    KeyCode::KeyW,
    KeyCode::KeyS,
    KeyCode::KeyA,
    KeyCode::KeyD,
    KeyCode::KeyE,
    KeyCode::KeyQ,
    KeyCode::ArrowLeft,
    KeyCode::ArrowRight,
    KeyCode::ArrowUp,
    KeyCode::ArrowDown,
];

/// Degrees per second for the arrow keys, and per pixel of mouse drag.
const LOOK_RATE: f64 = 60.0;
const DRAG_RATE: f64 = 0.25;

/// The key help printed by H.
const HELP: &str = "\
W/S forward/back, A/D left/right, E/Q up/down (Shift: faster)
arrows or left-drag: look; wheel or +/-: zoom; R: reset camera
Tab/Shift+Tab: select knob; [ ]: step it; P: screenshot; Escape: quit";

impl App {
    fn stop_worker(&mut self) {
        self.shared.lock().quit = true;
        self.shared.wake.notify_all();
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }

    /// Asks the rendering thread for the current camera and knobs.
    fn submit(&mut self) {
        let mut st = self.shared.lock();
        st.generation += 1;
        st.view = Some((self.camera.desc(), self.knobs));
        st.requested = Some(Instant::now());
        self.generation = st.generation;
        drop(st);
        self.shared.wake.notify_all();
    }

    fn fail(&mut self, el: &ActiveEventLoop, msg: String) {
        self.error = Some(msg);
        el.exit();
    }

    fn title(&self) -> String {
        let knob = knobs::KNOBS[self.selected].name;
        let all = knobs::summary(&self.knobs);
        match self.last {
            Some((s, passes, target)) => {
                let ms = s.trace_ms;
                format!(
                    "{} | {ms:.1} ms, {:.1} fps, {:.1} Mrays/s | {passes}/{target} spp | {all} | [{knob}]",
                    self.scene_name,
                    1e3 / ms.max(1e-9),
                    s.mrays_per_s()
                )
            }
            None => format!("{} | rendering | {all} | [{knob}]", self.scene_name),
        }
    }

    fn screenshot_path(&mut self) -> PathBuf {
        if let Some(p) = &self.screenshot {
            return p.clone();
        }
        loop {
            let stem = self
                .scene_name
                .split('.')
                .next()
                .unwrap_or("view")
                .to_string();
            let p = PathBuf::from(format!("{stem}-view-{:03}.png", self.shots));
            self.shots += 1;
            if !p.exists() {
                return p;
            }
        }
    }

    fn take_screenshot(&mut self) -> Result<PathBuf, String> {
        let path = self.screenshot_path();
        match &self.image {
            Some(img) => save_png(img, &path).map(|()| path),
            None => Err("no frame to save yet".into()),
        }
    }

    /// Blits the newest frame, scaled to the window (nearest pixel).
    fn present(&mut self) -> Result<(), String> {
        let (Some(window), Some(surface)) = (&self.window, &mut self.surface) else {
            return Ok(());
        };
        let size = window.inner_size();
        let (Some(ww), Some(wh)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height))
        else {
            return Ok(());
        };
        let err = |e: softbuffer::SoftBufferError| format!("tracer view: {e}");
        surface.resize(ww, wh).map_err(err)?;
        let mut buf = surface.buffer_mut().map_err(err)?;
        let (fw, fh) = self.engine_size;
        let (ww, wh) = (ww.get() as usize, wh.get() as usize);
        if self.pixels.len() != fw as usize * fh as usize {
            buf.fill(0);
        } else if (ww, wh) == (fw as usize, fh as usize) {
            buf.copy_from_slice(&self.pixels);
        } else {
            for (y, row) in buf.chunks_exact_mut(ww).enumerate() {
                let sy = y * fh as usize / wh;
                let src = &self.pixels[sy * fw as usize..][..fw as usize];
                for (x, p) in row.iter_mut().enumerate() {
                    *p = src[x * fw as usize / ww];
                }
            }
        }
        buf.present().map_err(err)
    }

    /// A frame is ready: show it, and move the script or benchmark on.
    fn on_frame(&mut self, el: &ActiveEventLoop) {
        let (frame, error) = {
            let mut st = self.shared.lock();
            (st.frame.take(), st.error.take())
        };
        if let Some(e) = error {
            eprintln!("tracer view: {e}");
        }
        let Some(frame) = frame else { return };
        self.pixels.clear();
        self.pixels
            .extend(frame.image.pixels.iter().map(|&p| pack_rgb(p)));
        self.image = Some(frame.image);
        self.last = Some((frame.stats, frame.passes, frame.target));
        if let Err(e) = self.present() {
            return self.fail(el, e);
        }
        if let Some(w) = &self.window {
            w.set_title(&self.title());
        }
        if frame.generation != self.generation {
            return;
        }
        match &mut self.mode {
            Mode::Interactive => {}
            Mode::Script { steps, next } => {
                if *next < steps.len() {
                    steps[*next].apply(&mut self.camera, &mut self.knobs);
                    *next += 1;
                    self.submit();
                } else if frame.passes >= frame.target {
                    if self.screenshot.is_some() {
                        if let Err(e) = self.take_screenshot() {
                            return self.fail(el, e);
                        }
                    }
                    el.exit();
                }
            }
            Mode::Bench(bench) => {
                // Frame time: from the request of the view to the frame on screen.
                let now = Instant::now();
                let ms = (now - frame.requested).as_secs_f64() * 1e3;
                bench.record(frame.stats, ms);
                if bench.done() {
                    return self.finish_bench(el);
                }
                self.camera = bench.camera(&self.home);
                self.submit();
            }
        }
    }

    fn finish_bench(&mut self, el: &ActiveEventLoop) {
        let Mode::Bench(bench) = &self.mode else {
            return;
        };
        let report = bench.report(&self.scene_name, self.engine_size, &self.knobs, "window");
        println!("{report}");
        if self.screenshot.is_some() {
            if let Err(e) = self.take_screenshot() {
                return self.fail(el, e);
            }
        }
        el.exit();
    }

    fn key(&mut self, el: &ActiveEventLoop, code: KeyCode, pressed: bool, repeat: bool) {
        if MOVE_KEYS.contains(&code) {
            if pressed {
                if self.held.is_empty() {
                    self.tick = Instant::now();
                }
                self.held.insert(code);
            } else {
                self.held.remove(&code);
            }
            return;
        }
        if !pressed || !matches!(self.mode, Mode::Interactive) && code != KeyCode::Escape {
            return;
        }
        let shift = self.modifiers.shift_key();
        match code {
            KeyCode::Escape => el.exit(),
            KeyCode::KeyR if !repeat => {
                self.camera.reset();
                self.submit();
            }
            KeyCode::Equal | KeyCode::NumpadAdd => {
                self.camera.zoom(1.0 / 1.1);
                self.submit();
            }
            KeyCode::Minus | KeyCode::NumpadSubtract => {
                self.camera.zoom(1.1);
                self.submit();
            }
            KeyCode::Tab => {
                let n = knobs::KNOBS.len();
                self.selected = (self.selected + if shift { n - 1 } else { 1 }) % n;
                if let Some(w) = &self.window {
                    w.set_title(&self.title());
                }
            }
            KeyCode::BracketLeft | KeyCode::BracketRight => {
                let d = if code == KeyCode::BracketRight { 1 } else { -1 };
                let before = self.knobs;
                (knobs::KNOBS[self.selected].step)(&mut self.knobs, d);
                if self.knobs != before {
                    self.submit();
                }
            }
            KeyCode::KeyP if !repeat => match self.take_screenshot() {
                Ok(p) => println!("screenshot: {}", p.display()),
                Err(e) => eprintln!("tracer view: {e}"),
            },
            KeyCode::KeyH | KeyCode::F1 => {
                println!("{HELP}");
                for k in knobs::KNOBS {
                    println!("  {:<10} {}", k.name, k.help);
                }
            }
            _ => {}
        }
    }

    /// Applies held movement keys for the time since the last tick.
    fn move_held(&mut self) -> bool {
        let now = Instant::now();
        let dt = (now - self.tick).as_secs_f64().min(0.1);
        self.tick = now;
        if self.held.is_empty() || !matches!(self.mode, Mode::Interactive) {
            return false;
        }
        let axis = |plus: KeyCode, minus: KeyCode| {
            (self.held.contains(&plus) as i32 - self.held.contains(&minus) as i32) as f64
        };
        let speed = self.camera.scale() * 0.5 * if self.modifiers.shift_key() { 4.0 } else { 1.0 };
        let (f, r, u) = (
            axis(KeyCode::KeyW, KeyCode::KeyS),
            axis(KeyCode::KeyD, KeyCode::KeyA),
            axis(KeyCode::KeyE, KeyCode::KeyQ),
        );
        let (yaw, pitch) = (
            axis(KeyCode::ArrowRight, KeyCode::ArrowLeft),
            axis(KeyCode::ArrowUp, KeyCode::ArrowDown),
        );
        if (f, r, u, yaw, pitch) == (0.0, 0.0, 0.0, 0.0, 0.0) {
            return false;
        }
        let d = speed * dt;
        self.camera.translate(f * d, r * d, u * d);
        self.camera
            .turn(yaw * LOOK_RATE * dt, pitch * LOOK_RATE * dt);
        true
    }
}

impl ApplicationHandler<()> for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = self.engine_size;
        let attrs = Window::default_attributes()
            .with_title(self.title())
            .with_inner_size(PhysicalSize::new(w, h));
        let window = match el.create_window(attrs) {
            Ok(w) => Rc::new(w),
            Err(e) => return self.fail(el, format!("tracer view: cannot open a window: {e}")),
        };
        let surface = softbuffer::Context::new(window.clone())
            .and_then(|ctx| softbuffer::Surface::new(&ctx, window.clone()));
        match surface {
            Ok(s) => self.surface = Some(s),
            Err(e) => return self.fail(el, format!("tracer view: cannot draw in the window: {e}")),
        }
        self.window = Some(window);
        if let Mode::Script { steps, next } = &mut self.mode {
            if let Some(step) = steps.first() {
                step.apply(&mut self.camera, &mut self.knobs);
                *next = 1;
            }
        }
        self.submit();
    }

    fn user_event(&mut self, el: &ActiveEventLoop, _: ()) {
        self.on_frame(el);
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => el.exit(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.present() {
                    self.fail(el, e);
                }
            }
            WindowEvent::Focused(false) => {
                self.held.clear();
                self.drag = None;
            }
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.key(el, code, event.state == ElementState::Pressed, event.repeat);
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let (Some((x0, y0)), Mode::Interactive) = (self.drag, &self.mode) {
                    let (dx, dy) = (position.x - x0, position.y - y0);
                    self.drag = Some(self.cursor);
                    self.camera.turn(dx * DRAG_RATE, -dy * DRAG_RATE);
                    self.submit();
                }
            }
            WindowEvent::MouseWheel { delta, .. } if matches!(self.mode, Mode::Interactive) => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                if lines != 0.0 {
                    self.camera.zoom(1.1f64.powf(-lines));
                    self.submit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, el: &ActiveEventLoop) {
        if self.move_held() {
            self.submit();
        }
        if self.held.is_empty() {
            el.set_control_flow(ControlFlow::Wait);
        } else {
            el.set_control_flow(ControlFlow::WaitUntil(
                Instant::now() + Duration::from_millis(15),
            ));
        }
    }
}
