//! Dynamic plugins: loading element kinds from a shared library (`cdylib`) at run time,
//! after checking that the library was built by the same compiler against the same
//! framework.
//!
//! What lives here: the ABI stamp ([`PluginAbi`]) every plugin exports, the loader
//! ([`load`]), the stamp comparison ([`check_stamp`]) and the macro plugin authors use,
//! [`export_plugin!`](crate::export_plugin), which generates the stamp and the entry point
//! so that they cannot be got wrong. What does not: the registry itself
//! ([`crate::registry`]), which the loaded kinds are handed to.
//!
//! # How a plugin is loaded
//!
//! 0. On ELF systems the file is read and checked first ([`crate::elf::check`]): a 64-bit
//!    shared object for this machine whose header tables, loadable segments and sections
//!    all lie within the file. A library copied only part way would otherwise be mapped
//!    and fault with SIGBUS; it is refused with its path instead.
//! 1. The file is opened with `dlopen` (`LoadLibrary` on Windows) through `libloading`. A
//!    file that is not a loadable library is refused with its path and the loader's reason.
//! 2. The exported static `RAILFEM_PLUGIN_ABI` ([`PluginAbi`], `#[repr(C)]`, only fixed-size
//!    byte arrays and integers, so it can be read whatever compiler built the library) is
//!    read *before any function of the library is called*: its magic number, layout
//!    revision, framework version, rustc version (with commit hash) and target triple must
//!    equal this process's own ([`PluginAbi::CURRENT`]); otherwise the load is refused with a
//!    one-line message saying what the plugin was built with, what this railfem is, and what
//!    to rebuild with. So must the versions of the crates whose types cross the boundary
//!    (nalgebra, serde, serde_json: [`PluginAbi::boundary_crates`], taken from the build's
//!    `Cargo.lock` by the framework's build script); a plugin built against another version
//!    is refused with one line naming the crate, both versions and the `cargo update` that
//!    fixes it.
//! 3. Only then is the entry point `railfem_plugin_register` called. It hands each of the
//!    plugin's [`ElementKind`]s to a closure of the host, which collects them; the host then
//!    registers them all in the **host** registry ([`registry::register`]) — all or none: a
//!    kind whose name is already taken refuses the whole plugin. (`inventory::submit!`
//!    inside a cdylib collects into the plugin's own copy of the framework, which the host
//!    never sees; that is why plugins register through the entry point.)
//! 4. The library is kept loaded until the process ends (it is never `dlclose`d: the
//!    elements it builds carry vtables and `&'static str`s that point into it). Loading the
//!    same file again (by canonical path) is a no-op.
//!
//! # The rule for plugin authors
//!
//! *Build the plugin with the same rustc, for the same target, against the same version of
//! `railfem-framework` (and of nalgebra, serde and serde_json) as the railfem that loads it* — in practice, build it in the same
//! workspace or with the same toolchain file — and export it with
//! [`export_plugin!`](crate::export_plugin). The stamp enforces the first sentence; the
//! macro the second. Across the boundary travel ordinary Rust types (`ElementKind` with
//! `fn` pointers, `Box<dyn Element>`, `Vec`, `String`, `serde_json::Value`) through the
//! unstable Rust ABI, which is sound only between identical compilers compiling identical
//! type definitions — exactly what the stamp checks. Further rules the stamp cannot check:
//!
//! - Neither the host nor the plugin may install a `#[global_allocator]`: boxes and vectors
//!   allocated on one side are freed on the other, which is only sound when both use the
//!   system allocator (the default for binaries and cdylibs alike).
//! - Kinds passed to the macro must be constant expressions (paths to `const` or `static`
//!   [`ElementKind`] items): the macro wraps each one's functions in functions of its own.
//! - A plugin must not rely on static constructors (`inventory::submit!`, `ctor`): those run
//!   inside `dlopen`, before the loader can read the stamp.
//!
//! # Traps verified while writing this (rustc 1.95, x86_64 Linux)
//!
//! - **A panic never crosses the boundary.** A cdylib links its own copy of `std`; a panic
//!   raised in it and unwinding into the host is a *foreign* exception for the host's `std`:
//!   a `catch_unwind` in the host does not catch it, the process aborts with "fatal runtime
//!   error: Rust cannot catch foreign exceptions" (tried with a two-file experiment: a cdylib
//!   whose `#[no_mangle] pub fn` panics, called under `catch_unwind` from a binary: exit 134).
//!   Hence the macro runs the registration under the *plugin's* `catch_unwind` and returns
//!   the panic as an `Err(String)`, and it wraps every factory, sample generator and every
//!   element the plugin builds in a guard (compiled into the plugin, so it uses the plugin's
//!   `catch_unwind`) that turns a panic into an [`ElementError`], a [`FemError`] or NaN
//!   outputs which the driver reports as non-finite. The host's registrar closure only
//!   pushes into a `Vec`, so no host panic can unwind through plugin frames either (the
//!   mirror-image trap). A host [`BuildContext`] method that panicked while a plugin factory
//!   calls it would still abort: the framework's contexts do not panic on valid node indices.
//! - **`env!("CARGO_PKG_VERSION")` inside a macro is the *caller's* version.** The stamp is
//!   therefore a `const` of this crate ([`PluginAbi::CURRENT`]) that the macro copies, so a
//!   plugin's stamp says which framework its own copy of the framework was, not the plugin
//!   package's version. Likewise rustc and target come from this crate's build script, which
//!   runs inside the plugin's build with the plugin's compiler.
//! - **The target triple is cargo's `TARGET`, not `rustc -vV`'s `host`**, so a cross-built
//!   plugin is stamped with what it was built for.
//! - **Static initialisers run before the stamp can be read.** `dlopen` runs a library's
//!   constructors; nothing here can check anything before that. The macro generates none.
//! - **Different optimisation levels are fine.** The integration test loads a dev-profile
//!   plugin into an opt-level-3 test binary; type layouts do not depend on the profile.
//! - **A refused library is never closed either**: its constructors may have registered
//!   thread-local destructors, and `dlclose` under them is a known crash; leaking one handle
//!   per refused file costs nothing.

use crate::element::{Element, ElementError, ElementProperties, NodeDofs, StepContext, TrialState};
use crate::error::FemError;
use crate::load_kind::{self, LoadKind};
use crate::recorder_kind::{self, RecorderKind};
use crate::registry::{self, BuildContext, ElementKind, ElementSpec, ParamDoc, Sample};
use libloading::Library;
use nalgebra::DMatrix;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

/// Magic number at the start of every [`PluginAbi`]: `"RAILFEM\x01"`.
pub const MAGIC: [u8; 8] = *b"RAILFEM\x01";

/// Revision of the plugin interface: the [`PluginAbi`] layout and the entry point's
/// signature ([`RegisterFn`]). Revision 2: the entry point hands [`PluginItem`]s (element,
/// load and recorder kinds), not element kinds alone. Revision 3: the stamp names the
/// versions of the crates whose types cross the boundary ([`PluginAbi::boundary_crates`]).
pub const ABI_REVISION: u32 = 3;

/// Name of the exported stamp static.
pub const ABI_SYMBOL: &str = "RAILFEM_PLUGIN_ABI";

/// Name of the exported entry point.
pub const REGISTER_SYMBOL: &str = "railfem_plugin_register";

/// One kind a plugin registers.
#[derive(Clone, Copy)]
pub enum PluginItem {
    /// An element kind ([`crate::registry`]).
    Element(ElementKind),
    /// A load kind ([`crate::load_kind`]).
    Load(LoadKind),
    /// A recorder kind ([`crate::recorder_kind`]).
    Recorder(RecorderKind),
}

impl PluginItem {
    /// The kind's type name.
    pub fn name(&self) -> &'static str {
        match self {
            PluginItem::Element(k) => k.name,
            PluginItem::Load(k) => k.name,
            PluginItem::Recorder(k) => k.name,
        }
    }

    /// What it is, for messages (`"element"`, `"load"`, `"recorder"`).
    pub fn what(&self) -> &'static str {
        match self {
            PluginItem::Element(_) => "element",
            PluginItem::Load(_) => "load",
            PluginItem::Recorder(_) => "recorder",
        }
    }

    fn taken(&self) -> bool {
        match self {
            PluginItem::Element(k) => registry::find(k.name).is_some(),
            PluginItem::Load(k) => load_kind::find(k.name).is_some(),
            PluginItem::Recorder(k) => recorder_kind::find(k.name).is_some(),
        }
    }

    fn register(self) -> Result<(), FemError> {
        match self {
            PluginItem::Element(k) => registry::register(k),
            PluginItem::Load(k) => load_kind::register(k),
            PluginItem::Recorder(k) => recorder_kind::register(k),
        }
    }
}

/// Signature of the entry point `railfem_plugin_register` that
/// [`export_plugin!`](crate::export_plugin) generates: it calls `registrar` once per
/// element, load and recorder kind and returns `Err(message)` if the plugin panicked (the
/// panic is caught on the plugin's side). Rust ABI: sound only between identical
/// compilers, which the stamp guarantees before this is ever called.
pub type RegisterFn = fn(registrar: &mut dyn FnMut(PluginItem)) -> Result<(), String>;

/// The version/ABI stamp a plugin exports as `#[no_mangle] static RAILFEM_PLUGIN_ABI`.
///
/// `#[repr(C)]` with fixed-size, NUL-padded byte arrays only, so it can be read from a
/// library built by any compiler. Build one with [`PluginAbi::CURRENT`] (the macro does).
#[repr(C)]
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct PluginAbi {
    /// Always [`MAGIC`].
    pub magic: [u8; 8],
    /// Layout revision of this struct ([`ABI_REVISION`]).
    pub abi_revision: u32,
    /// `railfem-framework` version the plugin was compiled against (NUL-padded UTF-8).
    pub framework_version: [u8; 32],
    /// First line of `rustc -vV` of the compiler that built the plugin (NUL-padded).
    pub rustc_version: [u8; 128],
    /// Target triple the plugin was built for (NUL-padded).
    pub target: [u8; 64],
    /// Versions of the crates whose types cross the boundary, as the build resolved them
    /// (`nalgebra 0.35.0;serde 1.0.228;serde_json 1.0.145`, NUL-padded; `unknown` where
    /// the build's `Cargo.lock` was not found). Stamped by the framework's build script.
    pub boundary_crates: [u8; 192],
}

/// The start of every stamp of every revision: read first, so that a stamp of another
/// layout is refused without reading past its end.
#[repr(C)]
#[derive(Clone, Copy)]
struct StampHead {
    magic: [u8; 8],
    abi_revision: u32,
}

/// Copies `s` into a NUL-padded array at compile time; a string that does not fit (leaving
/// at least one NUL) is a compile error.
pub const fn fixed<const N: usize>(s: &str) -> [u8; N] {
    let b = s.as_bytes();
    assert!(b.len() < N, "string too long for the plugin ABI stamp");
    let mut out = [0u8; N];
    let mut i = 0;
    while i < b.len() {
        out[i] = b[i];
        i += 1;
    }
    out
}

fn text(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8_lossy(&b[..end]).into_owned()
}

impl PluginAbi {
    /// The stamp of this build of the framework: its version, the rustc that compiled it
    /// and the target it was compiled for. In a plugin this is the plugin's copy of the
    /// framework, compiled by the plugin's compiler — which is what must match the host.
    pub const CURRENT: PluginAbi = PluginAbi {
        magic: MAGIC,
        abi_revision: ABI_REVISION,
        framework_version: fixed(env!("CARGO_PKG_VERSION")),
        rustc_version: fixed(env!("RAILFEM_RUSTC_VERSION")),
        target: fixed(env!("RAILFEM_TARGET")),
        boundary_crates: fixed(env!("RAILFEM_BOUNDARY_CRATES")),
    };

    /// The framework version as text.
    pub fn framework_version(&self) -> String {
        text(&self.framework_version)
    }

    /// The rustc version line as text.
    pub fn rustc_version(&self) -> String {
        text(&self.rustc_version)
    }

    /// The target triple as text.
    pub fn target(&self) -> String {
        text(&self.target)
    }

    /// The crates whose types cross the boundary with the versions the stamp names:
    /// `("nalgebra", "0.35.0")`, …; the version is `unknown` where the build could not tell.
    pub fn boundary_crates(&self) -> Vec<(String, String)> {
        text(&self.boundary_crates)
            .split(';')
            .filter_map(|e| {
                let (name, version) = e.trim().split_once(' ')?;
                Some((name.to_string(), version.trim().to_string()))
            })
            .collect()
    }

    fn describe(&self) -> String {
        format!(
            "framework {} / {} / target {}",
            self.framework_version(),
            self.rustc_version(),
            self.target()
        )
    }
}

impl std::fmt::Debug for PluginAbi {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PluginAbi")
            .field("magic", &self.magic)
            .field("abi_revision", &self.abi_revision)
            .field("framework_version", &self.framework_version())
            .field("rustc_version", &self.rustc_version())
            .field("target", &self.target())
            .field("boundary_crates", &text(&self.boundary_crates))
            .finish()
    }
}

/// Compares a plugin's stamp with this process's ([`PluginAbi::CURRENT`]). `path` names the
/// plugin in the message. A wrong magic number or layout revision means the symbol is not a
/// railfem stamp (or one from an incompatible era) and nothing else of it is trusted.
pub fn check_stamp(path: &Path, found: &PluginAbi) -> Result<(), FemError> {
    let host = PluginAbi::CURRENT;
    let shown = path.display();
    if found.magic != MAGIC || found.abi_revision != ABI_REVISION {
        return Err(FemError::Plugin(format!(
            "{shown}: `{ABI_SYMBOL}` is not a railfem {ABI_REVISION} stamp (magic {:?}, revision {}); rebuild the plugin against railfem-framework {} with export_plugin!",
            found.magic,
            found.abi_revision,
            host.framework_version()
        )));
    }
    if found.framework_version != host.framework_version
        || found.rustc_version != host.rustc_version
        || found.target != host.target
    {
        return Err(FemError::Plugin(format!(
            "{shown}: built with {} but this railfem is {}; rebuild the plugin with {} against railfem-framework {} for target {}",
            found.describe(),
            host.describe(),
            host.rustc_version(),
            host.framework_version(),
            host.target()
        )));
    }
    boundary_mismatch(path, found, &host)
}

/// The first crate crossing the boundary whose version differs between the plugin's
/// stamp and the host's, refused with both versions and the fix. A version the build
/// could not tell (`unknown`) is not compared.
fn boundary_mismatch(path: &Path, found: &PluginAbi, host: &PluginAbi) -> Result<(), FemError> {
    let theirs = found.boundary_crates();
    for (name, ours) in host.boundary_crates() {
        let Some((_, their)) = theirs.iter().find(|(n, _)| *n == name) else {
            continue;
        };
        if ours != "unknown" && *their != "unknown" && *their != ours {
            return Err(FemError::Plugin(format!(
                "{}: built against {name} {their} but this railfem uses {name} {ours}, whose types cross the plugin boundary; rebuild the plugin with {name} = \"={ours}\" (cargo update -p {name} --precise {ours})",
                path.display()
            )));
        }
    }
    Ok(())
}

struct Loaded {
    path: PathBuf,
    kinds: Vec<&'static str>,
    _lib: Library,
}

fn loaded_list() -> &'static Mutex<Vec<Loaded>> {
    static LIST: OnceLock<Mutex<Vec<Loaded>>> = OnceLock::new();
    LIST.get_or_init(|| Mutex::new(Vec::new()))
}

/// The plugins loaded so far: canonical path and the names of the kinds (element, load and
/// recorder) each registered.
pub fn loaded() -> Vec<(PathBuf, Vec<&'static str>)> {
    loaded_list()
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .map(|l| (l.path.clone(), l.kinds.clone()))
        .collect()
}

/// Loads the plugin library at `path` and registers its element kinds in the host
/// registry. See the module documentation for the order of checks. Loading a file that is
/// already loaded (same canonical path) does nothing. Every failure is a
/// [`FemError::Plugin`] whose one-line message starts with the path.
pub fn load(path: &Path) -> Result<(), FemError> {
    let shown = path.display();
    let canon = std::fs::canonicalize(path).map_err(|e| {
        FemError::Plugin(format!(
            "{shown}: cannot open the plugin file ({e}); give the path of the plugin's shared library (lib….so, ….dylib, ….dll)"
        ))
    })?;
    let mut list = loaded_list().lock().unwrap_or_else(|e| e.into_inner());
    if list.iter().any(|l| l.path == canon) {
        return Ok(());
    }
    check_file(&canon).map_err(|why| {
        FemError::Plugin(format!(
            "{shown}: damaged or foreign library: {why}; rebuild the plugin (cargo build --release -p …) or copy it again"
        ))
    })?;
    // SAFETY: opening a library runs its static constructors; that is inherent to dynamic
    // loading (see the module documentation). Nothing else of it runs before the stamp.
    let lib = unsafe { Library::new(&canon) }.map_err(|e| {
        FemError::Plugin(format!(
            "{shown}: not a loadable shared library ({}); give the path of a railfem plugin built as a cdylib",
            one_line(&error_chain(&e))
        ))
    })?;
    let result = register_from(&lib, path);
    match result {
        Ok(kinds) => {
            list.push(Loaded {
                path: canon,
                kinds,
                _lib: lib,
            });
            Ok(())
        }
        Err(e) => {
            // Never dlclose (see "A refused library is never closed").
            std::mem::forget(lib);
            Err(e)
        }
    }
}

/// The checks made before `dlopen` on ELF systems (not on macOS or Windows, whose
/// libraries are Mach-O and PE files).
fn check_file(path: &Path) -> Result<(), String> {
    if cfg!(any(target_os = "macos", target_os = "ios", windows)) {
        return Ok(());
    }
    crate::limits::check_file(path, "the library")?;
    let data = std::fs::read(path).map_err(|e| format!("cannot read it ({e})"))?;
    crate::elf::check(&data)
}

/// An error and its sources, joined with ": " (libloading's `Display` alone says only
/// "dlopen failed"; the loader's reason is the source).
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        s.push_str(": ");
        s.push_str(&c.to_string());
        cur = c.source();
    }
    s
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn register_from(lib: &Library, path: &Path) -> Result<Vec<&'static str>, FemError> {
    let shown = path.display();
    // SAFETY: the symbol is read as a pointer to a `#[repr(C)]` struct of plain bytes, which
    // is valid for any library that exports the name with at least that size; the magic
    // number is checked before any other field is trusted.
    let abi: PluginAbi = unsafe {
        let sym = lib
            .get::<*const PluginAbi>(ABI_SYMBOL.as_bytes())
            .map_err(|_| {
                FemError::Plugin(format!(
                    "{shown}: not a railfem plugin (no `{ABI_SYMBOL}` symbol); build it with railfem_framework::export_plugin! against railfem-framework {}",
                    PluginAbi::CURRENT.framework_version()
                ))
            })?;
        let p: *const PluginAbi = *sym;
        if p.is_null() {
            return Err(FemError::Plugin(format!(
                "{shown}: `{ABI_SYMBOL}` is a null symbol; build the plugin with export_plugin!"
            )));
        }
        // The head first: a stamp of another revision may be shorter than this one.
        let head = std::ptr::read_unaligned(p.cast::<StampHead>());
        if head.magic != MAGIC || head.abi_revision != ABI_REVISION {
            let mut shown_stamp = PluginAbi::CURRENT;
            shown_stamp.magic = head.magic;
            shown_stamp.abi_revision = head.abi_revision;
            return check_stamp(path, &shown_stamp).map(|()| Vec::new());
        }
        std::ptr::read_unaligned(p)
    };
    check_stamp(path, &abi)?;
    // SAFETY: the stamp says the library was built by this very compiler against this very
    // framework version for this target, so `RegisterFn` and every type it passes have the
    // same layout and calling convention on both sides; the plugin side catches its panics.
    let kinds = unsafe {
        let register = lib.get::<RegisterFn>(REGISTER_SYMBOL.as_bytes()).map_err(|_| {
            FemError::Plugin(format!(
                "{shown}: has a stamp but no `{REGISTER_SYMBOL}` entry point; build it with railfem_framework::export_plugin!"
            ))
        })?;
        let mut kinds: Vec<PluginItem> = Vec::new();
        // The closure cannot panic (a push), so nothing of the host unwinds through the
        // plugin's frames.
        let status = register(&mut |k| kinds.push(k));
        status.map_err(|m| {
            FemError::Plugin(format!(
                "{shown}: the plugin panicked while registering: {}",
                one_line(&m)
            ))
        })?;
        kinds
    };
    // All or none.
    for (i, k) in kinds.iter().enumerate() {
        let twice = kinds[..i]
            .iter()
            .any(|o| o.name() == k.name() && o.what() == k.what());
        if k.taken() || twice {
            return Err(FemError::Plugin(format!(
                "{shown}: {} type `{}` is already registered; rename the plugin's kind or load the plugin once",
                k.what(),
                k.name()
            )));
        }
    }
    let names = kinds.iter().map(|k| k.name()).collect();
    for k in kinds {
        k.register()?;
    }
    Ok(names)
}

/// Generates a plugin's ABI stamp and entry point from lists of kind constants (paths to
/// `const`/`static` [`ElementKind`], [`LoadKind`] and [`RecorderKind`] items). Write it
/// once at the crate root of a crate built with `crate-type = ["cdylib"]`:
///
/// ```ignore
/// pub const MY_KIND: railfem_framework::registry::ElementKind = /* … */;
/// railfem_framework::export_plugin!(MY_KIND);
/// // or, with loads and recorders (each list may be left out):
/// railfem_framework::export_plugin!(
///     elements: [MY_KIND],
///     loads: [MY_LOAD],
///     recorders: [MY_RECORDER],
/// );
/// ```
///
/// It emits `#[no_mangle] static RAILFEM_PLUGIN_ABI` (a copy of [`PluginAbi::CURRENT`] of
/// the plugin's framework) and `#[no_mangle] fn railfem_plugin_register` of type
/// [`RegisterFn`]. The registration, and every factory, sample generator, parameter
/// documentation function, element method, load and recorder of the exported kinds, runs
/// under the plugin's own `catch_unwind`, so a panic in the plugin becomes an error instead
/// of unwinding into the host (which would abort the process).
#[macro_export]
macro_rules! export_plugin {
    (
        $(elements: [$($kind:expr),* $(,)?])? $(,)?
        $(loads: [$($load:expr),* $(,)?])? $(,)?
        $(recorders: [$($rec:expr),* $(,)?])? $(,)?
    ) => {
        /// The railfem plugin ABI stamp, read by the loader before anything else.
        #[no_mangle]
        pub static RAILFEM_PLUGIN_ABI: $crate::plugin::PluginAbi =
            $crate::plugin::PluginAbi::CURRENT;

        /// The railfem plugin entry point: hands every element, load and recorder kind of
        /// this plugin to the host's registrar. Panics are caught on this side and returned
        /// as `Err`.
        #[no_mangle]
        pub fn railfem_plugin_register(
            registrar: &mut dyn FnMut($crate::plugin::PluginItem),
        ) -> ::std::result::Result<(), ::std::string::String> {
            // Type check against the loader's expectation.
            const _: $crate::plugin::RegisterFn = railfem_plugin_register;
            $crate::plugin::guard::catch("registration", || {
                $($({
                    fn build(
                        spec: &$crate::registry::ElementSpec,
                        ctx: &mut dyn $crate::registry::BuildContext,
                    ) -> ::std::result::Result<
                        ::std::boxed::Box<dyn $crate::element::Element>,
                        $crate::error::FemError,
                    > {
                        $crate::plugin::guard::build(&$kind, spec, ctx)
                    }
                    fn samples() -> ::std::vec::Vec<$crate::registry::Sample> {
                        $crate::plugin::guard::samples(&$kind)
                    }
                    fn params() -> ::std::vec::Vec<$crate::registry::ParamDoc> {
                        $crate::plugin::guard::params(&$kind)
                    }
                    let k: $crate::registry::ElementKind = $kind;
                    registrar($crate::plugin::PluginItem::Element(
                        $crate::registry::ElementKind {
                            build,
                            samples,
                            params,
                            ..k
                        },
                    ));
                })*)?
                $($({
                    fn build(
                        entry: &$crate::load_kind::LoadEntry,
                        model: &dyn $crate::lookup::ModelLookup,
                        origin: &str,
                    ) -> ::std::result::Result<
                        ::std::boxed::Box<dyn $crate::load_kind::AppliedLoad>,
                        $crate::error::FemError,
                    > {
                        $crate::plugin::guard::build_load(&$load, entry, model, origin)
                    }
                    fn params() -> ::std::vec::Vec<$crate::registry::ParamDoc> {
                        $crate::plugin::guard::docs($load.params)
                    }
                    let k: $crate::load_kind::LoadKind = $load;
                    registrar($crate::plugin::PluginItem::Load($crate::load_kind::LoadKind {
                        build: $crate::load_kind::LoadBuild::Factory(build),
                        params,
                        ..k
                    }));
                })*)?
                $($({
                    fn build(
                        entry: &$crate::recorder_kind::RecorderEntry,
                        model: &dyn $crate::lookup::ModelLookup,
                        origin: &str,
                    ) -> ::std::result::Result<
                        ::std::boxed::Box<dyn $crate::recorder_kind::RecordedColumns>,
                        $crate::error::FemError,
                    > {
                        $crate::plugin::guard::build_recorder(&$rec, entry, model, origin)
                    }
                    fn params() -> ::std::vec::Vec<$crate::registry::ParamDoc> {
                        $crate::plugin::guard::docs($rec.params)
                    }
                    let k: $crate::recorder_kind::RecorderKind = $rec;
                    registrar($crate::plugin::PluginItem::Recorder(
                        $crate::recorder_kind::RecorderKind {
                            build: $crate::recorder_kind::RecorderBuild::Factory(build),
                            params,
                            ..k
                        },
                    ));
                })*)?
            })
        }
    };
    ($($kind:expr),+ $(,)?) => {
        $crate::export_plugin!(elements: [$($kind),+]);
    };
}

/// Panic guards used by [`export_plugin!`](crate::export_plugin). Public only so the macro
/// can reach them; the code is compiled into the plugin, so `catch_unwind` here is the
/// plugin's own.
pub mod guard {
    use super::*;

    fn message(p: &(dyn std::any::Any + Send)) -> String {
        p.downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "(no message)".to_string())
    }

    /// Runs `f`, returning a panic as `Err("panic in <what>: <message>")`.
    pub fn catch(what: &str, f: impl FnOnce()) -> Result<(), String> {
        catch_unwind(AssertUnwindSafe(f))
            .map_err(|p| format!("panic in {what}: {}", message(p.as_ref())))
    }

    /// Calls the kind's factory under `catch_unwind` and wraps the element in a [`Guarded`].
    pub fn build(
        kind: &ElementKind,
        spec: &ElementSpec,
        ctx: &mut dyn BuildContext,
    ) -> Result<Box<dyn Element>, FemError> {
        match catch_unwind(AssertUnwindSafe(|| (kind.build)(spec, ctx))) {
            Ok(Ok(e)) => Ok(Box::new(Guarded::new(e))),
            Ok(Err(e)) => Err(e),
            Err(p) => Err(FemError::Plugin(format!(
                "{}: plugin element type `{}` panicked while building: {}",
                spec.origin,
                kind.name,
                message(p.as_ref())
            ))),
        }
    }

    /// Calls the kind's sample generator under `catch_unwind` (a panic gives no samples,
    /// which the conformance kit reports as a failure) and guards each element.
    pub fn samples(kind: &ElementKind) -> Vec<Sample> {
        match catch_unwind(AssertUnwindSafe(kind.samples)) {
            Ok(v) => v
                .into_iter()
                .map(|mut s| {
                    s.element = Box::new(Guarded::new(s.element));
                    s
                })
                .collect(),
            Err(_) => Vec::new(),
        }
    }

    /// Calls the kind's parameter documentation under `catch_unwind`.
    pub fn params(kind: &ElementKind) -> Vec<ParamDoc> {
        docs(kind.params)
    }

    /// Calls a parameter documentation function under `catch_unwind`.
    pub fn docs(f: fn() -> Vec<ParamDoc>) -> Vec<ParamDoc> {
        catch_unwind(AssertUnwindSafe(f)).unwrap_or_default()
    }

    /// Calls a load kind's factory under `catch_unwind` and wraps the load in a
    /// [`GuardedLoad`].
    pub fn build_load(
        kind: &LoadKind,
        entry: &crate::load_kind::LoadEntry,
        model: &dyn crate::lookup::ModelLookup,
        origin: &str,
    ) -> Result<Box<dyn crate::load_kind::AppliedLoad>, FemError> {
        let crate::load_kind::LoadBuild::Factory(f) = kind.build else {
            return Err(FemError::Plugin(format!(
                "{origin}: plugin load type `{}` has no factory; give it `build: LoadBuild::Factory(…)`",
                kind.name
            )));
        };
        match catch_unwind(AssertUnwindSafe(|| f(entry, model, origin))) {
            Ok(Ok(l)) => Ok(Box::new(GuardedLoad {
                inner: l,
                kind: kind.name,
            })),
            Ok(Err(e)) => Err(e),
            Err(p) => Err(FemError::Plugin(format!(
                "{origin}: plugin load type `{}` panicked while building: {}",
                kind.name,
                message(p.as_ref())
            ))),
        }
    }

    /// A plugin's load whose methods run under the plugin's `catch_unwind`: a panic
    /// becomes an error that stops the run.
    #[derive(Debug)]
    pub struct GuardedLoad {
        inner: Box<dyn crate::load_kind::AppliedLoad>,
        kind: &'static str,
    }

    impl crate::load_kind::AppliedLoad for GuardedLoad {
        fn nodal_forces(
            &self,
            t: f64,
            add: &mut dyn FnMut(usize, crate::dof::Dof, f64),
        ) -> Result<(), FemError> {
            catch_unwind(AssertUnwindSafe(|| self.inner.nodal_forces(t, add))).unwrap_or_else(|p| {
                Err(FemError::Plugin(format!(
                    "panic in plugin load `{}` at t = {t} s: {}",
                    self.kind,
                    message(p.as_ref())
                )))
            })
        }
        fn nodes(&self) -> Vec<usize> {
            catch_unwind(AssertUnwindSafe(|| self.inner.nodes())).unwrap_or_default()
        }
    }

    /// Calls a recorder kind's factory under `catch_unwind` and wraps the recorder in a
    /// [`GuardedRecorder`].
    pub fn build_recorder(
        kind: &RecorderKind,
        entry: &crate::recorder_kind::RecorderEntry,
        model: &dyn crate::lookup::ModelLookup,
        origin: &str,
    ) -> Result<Box<dyn crate::recorder_kind::RecordedColumns>, FemError> {
        let crate::recorder_kind::RecorderBuild::Factory(f) = kind.build else {
            return Err(FemError::Plugin(format!(
                "{origin}: plugin recorder type `{}` has no factory; give it `build: RecorderBuild::Factory(…)`",
                kind.name
            )));
        };
        match catch_unwind(AssertUnwindSafe(|| f(entry, model, origin))) {
            Ok(Ok(r)) => Ok(Box::new(GuardedRecorder {
                inner: r,
                kind: kind.name,
            })),
            Ok(Err(e)) => Err(e),
            Err(p) => Err(FemError::Plugin(format!(
                "{origin}: plugin recorder type `{}` panicked while building: {}",
                kind.name,
                message(p.as_ref())
            ))),
        }
    }

    /// A plugin's recorder whose methods run under the plugin's `catch_unwind`: a panic in
    /// `row` becomes an error that stops the run; one in `columns` gives no columns.
    pub struct GuardedRecorder {
        inner: Box<dyn crate::recorder_kind::RecordedColumns>,
        kind: &'static str,
    }

    impl crate::recorder_kind::RecordedColumns for GuardedRecorder {
        fn columns(&self) -> Vec<String> {
            catch_unwind(AssertUnwindSafe(|| self.inner.columns())).unwrap_or_default()
        }
        fn row(
            &mut self,
            s: &mut crate::recorder_kind::RecordState,
            out: &mut Vec<f64>,
        ) -> Result<(), FemError> {
            let t = s.t;
            catch_unwind(AssertUnwindSafe(|| self.inner.row(s, out))).unwrap_or_else(|p| {
                Err(FemError::Plugin(format!(
                    "panic in plugin recorder `{}` at t = {t} s: {}",
                    self.kind,
                    message(p.as_ref())
                )))
            })
        }
        fn writes_rows(&self) -> bool {
            catch_unwind(AssertUnwindSafe(|| self.inner.writes_rows())).unwrap_or(true)
        }
        fn finish(
            &mut self,
            out: &mut dyn std::io::Write,
            path: &std::path::Path,
        ) -> Result<(), FemError> {
            catch_unwind(AssertUnwindSafe(|| self.inner.finish(out, path))).unwrap_or_else(|p| {
                Err(FemError::Plugin(format!(
                    "panic in plugin recorder `{}` while finishing its file: {}",
                    self.kind,
                    message(p.as_ref())
                )))
            })
        }
        fn nodes(&self) -> Vec<usize> {
            catch_unwind(AssertUnwindSafe(|| self.inner.nodes())).unwrap_or_default()
        }
    }

    /// An element of a plugin whose every method runs under the plugin's `catch_unwind`.
    /// After a panic the element is *poisoned*: `update` and `advance` return an
    /// [`ElementError`] naming the panic, and forces and matrices are filled with NaN so
    /// the driver stops with a non-finite-value error instead of aborting.
    pub struct Guarded {
        inner: Box<dyn Element>,
        kind: String,
        poisoned: Mutex<Option<String>>,
        connectivity: Vec<NodeDofs>,
    }

    impl Guarded {
        /// Wraps `inner`.
        pub fn new(inner: Box<dyn Element>) -> Guarded {
            let kind = inner.kind().to_string();
            let connectivity = inner.connectivity().to_vec();
            Guarded {
                inner,
                kind,
                poisoned: Mutex::new(None),
                connectivity,
            }
        }

        fn poison(&self, what: &str, p: Box<dyn std::any::Any + Send>) -> String {
            let m = format!(
                "panic in plugin element `{}` ({what}): {}",
                self.kind,
                message(p.as_ref())
            );
            *self.poisoned.lock().unwrap_or_else(|e| e.into_inner()) = Some(m.clone());
            m
        }

        fn poisoned(&self) -> Option<String> {
            self.poisoned
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clone()
        }

        fn nan_on_panic(&self, what: &str, out: &mut [f64], f: impl FnOnce(&mut [f64])) {
            if self.poisoned().is_some() {
                out.fill(f64::NAN);
                return;
            }
            if let Err(p) = catch_unwind(AssertUnwindSafe(|| f(&mut *out))) {
                self.poison(what, p);
                out.fill(f64::NAN);
            }
        }
    }

    impl Element for Guarded {
        fn kind(&self) -> &str {
            &self.kind
        }
        fn connectivity(&self) -> &[NodeDofs] {
            &self.connectivity
        }
        fn properties(&self) -> ElementProperties {
            catch_unwind(AssertUnwindSafe(|| self.inner.properties())).unwrap_or_default()
        }
        fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
            if let Some(m) = self.poisoned() {
                return Err(ElementError::Invalid(m));
            }
            match catch_unwind(AssertUnwindSafe(|| self.inner.advance(ctx))) {
                Ok(Ok(changed)) => {
                    if changed {
                        self.connectivity = self.inner.connectivity().to_vec();
                    }
                    Ok(changed)
                }
                Ok(Err(e)) => Err(e),
                Err(p) => Err(ElementError::Invalid(self.poison("advance", p))),
            }
        }
        fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
            if let Some(m) = self.poisoned() {
                return Err(ElementError::Invalid(m));
            }
            match catch_unwind(AssertUnwindSafe(|| self.inner.update(trial))) {
                Ok(r) => r,
                Err(p) => Err(ElementError::Invalid(self.poison("update", p))),
            }
        }
        fn resisting_force(&self, f: &mut [f64]) {
            self.nan_on_panic("resisting_force", f, |f| self.inner.resisting_force(f));
        }
        fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
            self.nan_on_panic("tangent_stiffness", k.as_mut_slice(), |s| {
                let mut m = DMatrix::zeros(self.inner.ndof(), self.inner.ndof());
                self.inner.tangent_stiffness(&mut m);
                s.copy_from_slice(m.as_slice());
            });
        }
        fn mass(&self, m: &mut DMatrix<f64>) {
            self.nan_on_panic("mass", m.as_mut_slice(), |s| {
                let mut x = DMatrix::zeros(self.inner.ndof(), self.inner.ndof());
                self.inner.mass(&mut x);
                s.copy_from_slice(x.as_slice());
            });
        }
        fn damping(&self, c: &mut DMatrix<f64>) {
            self.nan_on_panic("damping", c.as_mut_slice(), |s| {
                let mut x = DMatrix::zeros(self.inner.ndof(), self.inner.ndof());
                self.inner.damping(&mut x);
                s.copy_from_slice(x.as_slice());
            });
        }
        fn commit(&mut self) {
            if self.poisoned().is_none() {
                if let Err(p) = catch_unwind(AssertUnwindSafe(|| self.inner.commit())) {
                    self.poison("commit", p);
                }
            }
        }
        fn revert(&mut self) {
            if self.poisoned().is_none() {
                if let Err(p) = catch_unwind(AssertUnwindSafe(|| self.inner.revert())) {
                    self.poison("revert", p);
                }
            }
        }
        fn output_names(&self) -> Vec<String> {
            catch_unwind(AssertUnwindSafe(|| self.inner.output_names())).unwrap_or_default()
        }

        fn output_units(&self) -> Vec<String> {
            catch_unwind(AssertUnwindSafe(|| self.inner.output_units())).unwrap_or_default()
        }
        fn outputs(&self, out: &mut Vec<f64>) {
            let n = out.len();
            if catch_unwind(AssertUnwindSafe(|| self.inner.outputs(&mut *out))).is_err() {
                out.truncate(n);
                out.extend(self.output_names().iter().map(|_| f64::NAN));
            }
        }
        fn parameters(&self) -> serde_json::Value {
            catch_unwind(AssertUnwindSafe(|| self.inner.parameters()))
                .unwrap_or(serde_json::Value::Null)
        }
        fn dissipated_energy(&self) -> f64 {
            catch_unwind(AssertUnwindSafe(|| self.inner.dissipated_energy())).unwrap_or(f64::NAN)
        }
        fn dissipation_kind(&self) -> crate::element::DissipationKind {
            catch_unwind(AssertUnwindSafe(|| self.inner.dissipation_kind()))
                .unwrap_or(crate::element::DissipationKind::Material)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn current_stamp_is_accepted_and_readable() {
        let s = PluginAbi::CURRENT;
        assert!(check_stamp(Path::new("x.so"), &s).is_ok());
        assert_eq!(s.framework_version(), env!("CARGO_PKG_VERSION"));
        assert!(s.rustc_version().starts_with("rustc "), "{:?}", s);
        assert!(!s.target().is_empty());
    }

    #[test]
    fn forged_stamps_are_refused_with_a_clear_line() {
        let mut s = PluginAbi::CURRENT;
        s.rustc_version = fixed("rustc 1.0.0 (a59807616 2015-05-15)");
        let e = check_stamp(Path::new("/p/libx.so"), &s).unwrap_err();
        let m = e.to_string();
        assert!(matches!(e, FemError::Plugin(_)));
        assert!(m.contains("/p/libx.so: built with framework"), "{m}");
        assert!(m.contains("rustc 1.0.0"), "{m}");
        assert!(m.contains(&PluginAbi::CURRENT.rustc_version()), "{m}");
        assert!(m.contains("rebuild the plugin with"), "{m}");
        assert!(!m.contains('\n'));

        let mut s = PluginAbi::CURRENT;
        s.magic = *b"NOTRAIL!";
        let m = check_stamp(Path::new("q.so"), &s).unwrap_err().to_string();
        assert!(m.contains("q.so") && m.contains("not a railfem"), "{m}");
    }

    /// The host's stamp names nalgebra, serde and serde_json with the versions of this
    /// workspace's Cargo.lock (the build script read them from it).
    #[test]
    fn the_stamp_names_the_boundary_crates_of_the_lock_file() {
        let lock = include_str!("../../Cargo.lock");
        let ours = PluginAbi::CURRENT.boundary_crates();
        let names: Vec<&str> = ours.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["nalgebra", "serde", "serde_json"]);
        for (name, version) in &ours {
            let entry = format!("name = \"{name}\"\nversion = \"{version}\"\n");
            assert!(
                lock.contains(&entry),
                "{name} {version} is not in Cargo.lock"
            );
        }
    }

    /// A plugin built against another version of a crate whose types cross the boundary is
    /// refused with one line naming the crate and both versions; a version its build could
    /// not tell is not compared.
    #[test]
    fn a_plugin_on_another_nalgebra_is_refused_naming_both_versions() {
        let host = PluginAbi::CURRENT;
        let ours = host.boundary_crates();
        let nalgebra = &ours[0].1;
        let stamp = |nalgebra_version: &str| {
            let text: Vec<String> = ours
                .iter()
                .map(|(n, v)| match n.as_str() {
                    "nalgebra" => format!("{n} {nalgebra_version}"),
                    _ => format!("{n} {v}"),
                })
                .collect();
            let mut s = host;
            s.boundary_crates = fixed(&text.join(";"));
            s
        };
        let e = check_stamp(Path::new("/p/libold.so"), &stamp("0.33.2")).unwrap_err();
        let m = e.to_string();
        assert!(matches!(e, FemError::Plugin(_)));
        assert!(!m.contains('\n'), "{m}");
        assert!(
            m.contains(&format!(
                "/p/libold.so: built against nalgebra 0.33.2 but this railfem uses nalgebra {nalgebra}"
            )),
            "{m}"
        );
        assert!(m.contains(&format!("nalgebra = \"={nalgebra}\"")), "{m}");
        assert!(check_stamp(Path::new("x.so"), &stamp("unknown")).is_ok());
        assert!(check_stamp(Path::new("x.so"), &stamp(nalgebra)).is_ok());
    }

    /// An element that panics in `update` once `armed`.
    struct Bomb {
        nodes: [NodeDofs; 1],
    }

    impl Element for Bomb {
        fn kind(&self) -> &str {
            "bomb"
        }
        fn connectivity(&self) -> &[NodeDofs] {
            &self.nodes
        }
        fn properties(&self) -> ElementProperties {
            ElementProperties::default()
        }
        fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
            if t.disp[0] > 1.0 {
                panic!("displacement too large");
            }
            Ok(())
        }
        fn resisting_force(&self, f: &mut [f64]) {
            f[0] = 1.0;
        }
        fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
            k[(0, 0)] = 1.0;
        }
    }

    #[test]
    fn guard_turns_a_panic_into_an_error_and_poisons() {
        let mut g = guard::Guarded::new(Box::new(Bomb {
            nodes: [NodeDofs::all(0)],
        }));
        let t = |d: f64| [d, 0.0, 0.0, 0.0, 0.0, 0.0];
        let z = [0.0; 6];
        let ok = t(0.5);
        fn st<'a>(u: &'a [f64; 6], z: &'a [f64; 6]) -> TrialState<'a> {
            TrialState {
                time: 0.0,
                dt: 0.0,
                disp: u,
                vel: z,
                acc: z,
            }
        }
        assert!(g.update(&st(&ok, &z)).is_ok());
        let mut f = [0.0; 6];
        g.resisting_force(&mut f);
        assert_eq!(f[0], 1.0);
        let bad = t(2.0);
        let e = g.update(&st(&bad, &z)).unwrap_err().to_string();
        assert!(e.contains("panic in plugin element `bomb` (update)"), "{e}");
        assert!(e.contains("displacement too large"), "{e}");
        // Poisoned from now on: errors and NaN, never a second panic.
        assert!(g.update(&st(&ok, &z)).is_err());
        g.resisting_force(&mut f);
        assert!(f.iter().all(|x| x.is_nan()));
    }

    #[test]
    fn missing_file_names_the_path() {
        let m = load(Path::new("/nonexistent/libnope.so"))
            .unwrap_err()
            .to_string();
        assert!(m.contains("/nonexistent/libnope.so"), "{m}");
    }
}
