//! What a Python process keeps between calls: the devices it opened (each GPU renderer with its
//! compiled kernels, so a loop of renders compiles once), the device `auto` chose per scene,
//! and the runner that does the work off the interpreter's lock while the interpreter's thread
//! shows progress and takes Ctrl-C.

use crate::error;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, OnceLock};
use std::time::Duration;
use stratapt_cli::device::{Device, DeviceChoice};
use stratapt_gpu::adapter;
use stratapt_scene::{FlatScene, RenderSettings};

/// How often the interpreter's thread looks at Ctrl-C and progress while work runs.
const POLL: Duration = Duration::from_millis(100);

/// A device chosen for a render, and why (`auto`'s reason).
pub type Chosen = (Arc<Device>, Option<String>);

/// The devices this process has opened, by adapter (name, backend, driver).
fn opened() -> &'static Mutex<HashMap<String, Arc<Device>>> {
    static OPENED: OnceLock<Mutex<HashMap<String, Arc<Device>>>> = OnceLock::new();
    OPENED.get_or_init(Default::default)
}

/// The devices chosen so far, by what the choice depends on (the device and adapter asked
/// for; under `auto` also the scene and its settings, which lavapipe's probe measures).
fn chosen() -> &'static Mutex<HashMap<String, Chosen>> {
    static CHOSEN: OnceLock<Mutex<HashMap<String, Chosen>>> = OnceLock::new();
    CHOSEN.get_or_init(Default::default)
}

/// The device for a render of `scene` with `settings`, as the command chooses it (see
/// [`Device::choose`]), opened once per process and adapter.
pub fn device(
    choice: DeviceChoice,
    adapter: Option<&str>,
    scene: &FlatScene,
    settings: &RenderSettings,
) -> anyhow::Result<Chosen> {
    let mut key = format!("{choice:?} {adapter:?}");
    if choice == DeviceChoice::Auto && adapter.is_none() {
        let (w, h) = (scene.camera.width, scene.camera.height);
        key += &format!(" {w}x{h} {:x} {settings:?}", scene.content_hash());
    }
    let mut chosen = chosen().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(found) = chosen.get(&key) {
        return Ok(found.clone());
    }
    // The probe renders the scene at its own size and gives it back: a copy to lend it.
    let mut probe = (choice == DeviceChoice::Auto).then(|| FlatScene::clone(scene));
    let made = Device::choose_with(
        choice,
        adapter,
        probe.as_mut().map(|s: &mut FlatScene| (s, settings)),
        &mut open,
    )?;
    chosen.insert(key, made.clone());
    Ok(made)
}

/// The renderer on `adapter`: the one this process opened, or a new one.
pub fn open(adapter: wgpu::Adapter) -> anyhow::Result<Arc<Device>> {
    let info = adapter.get_info();
    let key = format!("{} | {:?} | {}", info.name, info.backend, info.driver_info);
    let mut opened = opened().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(device) = opened.get(&key) {
        return Ok(device.clone());
    }
    let device = Arc::new(Device::open(adapter)?);
    opened.insert(key, device.clone());
    Ok(device)
}

/// What running work shares with the interpreter's thread: the cancel flag (Ctrl-C), the
/// samples done (progress), whether it has finished.
#[derive(Default)]
pub struct Watch {
    pub cancel: AtomicBool,
    done: AtomicU64,
    finished: Mutex<bool>,
    wake: Condvar,
}

impl Watch {
    /// `n` more samples done.
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    fn finish(&self) {
        *self.finished.lock().unwrap_or_else(|e| e.into_inner()) = true;
        self.wake.notify_all();
    }

    /// Wait until the work has finished or `timeout` has passed; whether it has finished.
    fn wait(&self, timeout: Duration) -> bool {
        let finished = self.finished.lock().unwrap_or_else(|e| e.into_inner());
        let (finished, _) = self
            .wake
            .wait_timeout_while(finished, timeout, |f| !*f)
            .unwrap_or_else(|e| e.into_inner());
        *finished
    }
}

/// Run `work` on a thread of its own, off the interpreter's lock, while this thread calls
/// `progress(samples_done)` every [`POLL`] and runs Python's signal handlers: Ctrl-C
/// (`KeyboardInterrupt`) or an exception from `progress` sets the cancel flag, waits for the
/// work to stop (a render finishes its batch, so what it returns is whole), and is raised.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Watch) -> T + Send,
) -> PyResult<T> {
    let watch = Watch::default();
    std::thread::scope(|s| {
        let worker = s.spawn(|| {
            // Finished even if the work panics, so the interpreter's thread stops waiting.
            struct Finish<'a>(&'a Watch);
            impl Drop for Finish<'_> {
                fn drop(&mut self) {
                    self.0.finish();
                }
            }
            let _finish = Finish(&watch);
            work(&watch)
        });
        let mut raised: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| watch.wait(POLL));
            if let (Some(progress), None) = (progress, &raised) {
                if let Err(e) = progress.call1((watch.done.load(Ordering::Relaxed),)) {
                    raised = Some(e);
                }
            }
            if raised.is_none() {
                raised = py.check_signals().err();
            }
            if raised.is_some() {
                watch.cancel.store(true, Ordering::SeqCst);
            }
            if finished {
                break;
            }
        }
        let result = py.detach(|| worker.join());
        match (raised, result) {
            (Some(e), _) => Err(e),
            (None, Ok(value)) => Ok(value),
            (None, Err(_)) => Err(error::runtime(
                "strata panicked (a bug: please report it with the scene)",
            )),
        }
    })
}

/// The GPU adapters wgpu finds, best first (the one `device="gpu"` takes), as `strata
/// adapters` lists them: name, backend, type, description, storage buffers per stage, largest
/// storage buffer in MiB, timestamp queries.
#[pyfunction]
pub fn adapters(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let found = py.detach(adapter::ranked);
    found
        .iter()
        .map(|a| {
            let info = a.get_info();
            let limits = a.limits();
            let d = PyDict::new(py);
            d.set_item("name", &info.name)?;
            d.set_item("backend", info.backend.to_str())?;
            d.set_item("type", format!("{:?}", info.device_type))?;
            d.set_item("driver", &info.driver_info)?;
            d.set_item("description", adapter::describe(&info))?;
            d.set_item(
                "storage_buffers",
                limits.max_storage_buffers_per_shader_stage,
            )?;
            d.set_item(
                "max_storage_buffer_mib",
                limits.max_storage_buffer_binding_size >> 20,
            )?;
            d.set_item(
                "timestamps",
                a.features().contains(wgpu::Features::TIMESTAMP_QUERY),
            )?;
            Ok(d)
        })
        .collect()
}
