//! The few functions of Open Image Denoise's C API (`OpenImageDenoise/oidn.h`,
//! version 2) that denoising needs, looked up by name in the library opened at run
//! time, and the one call sequence that uses them: a CPU device, an `RT` filter over
//! shared float images.
//!
//! The crate's `unsafe` here is calling into that library: every pointer handed to
//! it is a live Rust slice of the size declared with it, and the handles it returns
//! are released exactly once ([`Oidn`]'s and [`Filter`]'s `Drop`).
#![allow(unsafe_code)]

use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::Path;

use libloading::Library;

/// `OIDNDevice`, `OIDNFilter`: opaque handles.
type Handle = *mut c_void;

/// `OIDN_DEVICE_TYPE_CPU`.
const DEVICE_CPU: c_int = 1;
/// `OIDN_FORMAT_FLOAT3`: three 32-bit floats per pixel.
const FORMAT_FLOAT3: c_int = 3;
/// `OIDN_ERROR_NONE`.
const ERROR_NONE: c_int = 0;

/// The entry points, copied out of the library (which [`Oidn`] keeps open).
struct Functions {
    new_device: unsafe extern "C" fn(c_int) -> Handle,
    set_device_int: unsafe extern "C" fn(Handle, *const c_char, c_int),
    get_device_int: unsafe extern "C" fn(Handle, *const c_char) -> c_int,
    commit_device: unsafe extern "C" fn(Handle),
    release_device: unsafe extern "C" fn(Handle),
    device_error: unsafe extern "C" fn(Handle, *mut *const c_char) -> c_int,
    new_filter: unsafe extern "C" fn(Handle, *const c_char) -> Handle,
    set_shared_image:
        unsafe extern "C" fn(Handle, *const c_char, *mut c_void, c_int, usize, usize, usize, usize, usize),
    set_filter_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    set_filter_int: unsafe extern "C" fn(Handle, *const c_char, c_int),
    commit_filter: unsafe extern "C" fn(Handle),
    execute_filter: unsafe extern "C" fn(Handle),
    release_filter: unsafe extern "C" fn(Handle),
}

/// An opened Open Image Denoise library with one committed CPU device; the device
/// is released when dropped, then the library closed.
pub struct Oidn {
    functions: Functions,
    device: Handle,
    // Last: the functions above point into it, so it closes after they are gone.
    _library: Library,
}

// SAFETY: Open Image Denoise's API is thread-safe ("operations that use the same
// device are serialized"), and the handle is the library's, tied to no thread.
unsafe impl Send for Oidn {}
unsafe impl Sync for Oidn {}

/// `library.get(name)`, as a copied function pointer of type `T`.
///
/// # Safety
/// `T` must be the function's type as the C header declares it.
unsafe fn symbol<T: Copy>(library: &Library, name: &[u8]) -> Result<T, String> {
    let found = unsafe { library.get::<T>(name) };
    found.map(|s| *s).map_err(|e| e.to_string())
}

impl Oidn {
    /// Opens the library at `path` (a path with a `/` is opened as it is; a bare
    /// file name goes through the system's search), finds its entry points and
    /// makes a CPU device on `threads` threads (0: one per core).
    pub fn open(path: &Path, threads: u32) -> Result<Oidn, String> {
        // SAFETY: opening runs the library's initialisers; Open Image Denoise's do
        // nothing but register its devices.
        let library = unsafe { Library::new(path) }.map_err(|e| e.to_string())?;
        // SAFETY: each name is looked up with the signature oidn.h (version 2) gives it.
        let functions = unsafe {
            Functions {
                new_device: symbol(&library, b"oidnNewDevice\0")?,
                set_device_int: symbol(&library, b"oidnSetDeviceInt\0")?,
                get_device_int: symbol(&library, b"oidnGetDeviceInt\0")?,
                commit_device: symbol(&library, b"oidnCommitDevice\0")?,
                release_device: symbol(&library, b"oidnReleaseDevice\0")?,
                device_error: symbol(&library, b"oidnGetDeviceError\0")?,
                new_filter: symbol(&library, b"oidnNewFilter\0")?,
                set_shared_image: symbol(&library, b"oidnSetSharedFilterImage\0")?,
                set_filter_bool: symbol(&library, b"oidnSetFilterBool\0")?,
                set_filter_int: symbol(&library, b"oidnSetFilterInt\0")?,
                commit_filter: symbol(&library, b"oidnCommitFilter\0")?,
                execute_filter: symbol(&library, b"oidnExecuteFilter\0")?,
                release_filter: symbol(&library, b"oidnReleaseFilter\0")?,
            }
        };
        // SAFETY: a plain constructor; a null handle is checked below.
        let device = unsafe { (functions.new_device)(DEVICE_CPU) };
        if device.is_null() {
            return Err("it has no CPU device for this processor".into());
        }
        let oidn = Oidn {
            functions,
            device,
            _library: library,
        };
        let threads = c_int::try_from(threads).unwrap_or(c_int::MAX);
        // SAFETY: a live device handle and NUL-terminated names.
        unsafe {
            (oidn.functions.set_device_int)(device, c"numThreads".as_ptr(), threads);
            (oidn.functions.commit_device)(device);
        }
        oidn.check()?;
        Ok(oidn)
    }

    /// The library's version as `major * 10000 + minor * 100 + patch`.
    pub fn version(&self) -> i32 {
        // SAFETY: a live device handle and a NUL-terminated name.
        unsafe { (self.functions.get_device_int)(self.device, c"version".as_ptr()) }
    }

    /// The device's first error since the last check, as its message.
    fn check(&self) -> Result<(), String> {
        let mut message: *const c_char = std::ptr::null();
        // SAFETY: a live device handle; the message, if any, is a NUL-terminated
        // string the library owns until its next call, copied at once.
        let code = unsafe { (self.functions.device_error)(self.device, &mut message) };
        if code == ERROR_NONE {
            return Ok(());
        }
        let text = if message.is_null() {
            String::new()
        } else {
            // SAFETY: see above.
            unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned()
        };
        Err(format!("error {code}: {text}"))
    }

    /// Runs the `RT` filter: `output` (`3 * width * height` floats, RGB rows, top
    /// first) receives the denoised `color`, guided by `albedo` and `normal` of the
    /// same layout; `hdr` says that colours may exceed 1; `clean_aux` that the
    /// guides have no noise of their own; `quality` is `OIDNQuality` (4 fast, 5
    /// balanced, 6 high).
    #[allow(clippy::too_many_arguments)]
    pub fn filter_rt(
        &self,
        (width, height): (usize, usize),
        color: &[f32],
        albedo: &[f32],
        normal: &[f32],
        output: &mut [f32],
        hdr: bool,
        clean_aux: bool,
        quality: c_int,
    ) -> Result<(), String> {
        let n = 3 * width * height;
        assert!(
            [color.len(), albedo.len(), normal.len(), output.len()] == [n; 4],
            "images of 3 x {width} x {height} floats"
        );
        let f = &self.functions;
        // SAFETY: a live device handle and a NUL-terminated name; null is checked.
        let handle = unsafe { (f.new_filter)(self.device, c"RT".as_ptr()) };
        if handle.is_null() {
            self.check()?;
            return Err("it has no RT filter".into());
        }
        let filter = Filter { oidn: self, handle };
        let images: [(&CStr, *mut c_void); 4] = [
            (c"color", color.as_ptr() as *mut c_void),
            (c"albedo", albedo.as_ptr() as *mut c_void),
            (c"normal", normal.as_ptr() as *mut c_void),
            (c"output", output.as_mut_ptr() as *mut c_void),
        ];
        let row = 3 * 4 * width;
        for (name, data) in images {
            // SAFETY: each pointer is a live slice of exactly `height` rows of
            // `row` bytes, pixels 12 bytes apart, outliving the filter (released
            // at the end of this call); the library writes through "output" only.
            unsafe {
                (f.set_shared_image)(
                    filter.handle,
                    name.as_ptr(),
                    data,
                    FORMAT_FLOAT3,
                    width,
                    height,
                    0,
                    12,
                    row,
                )
            };
        }
        // SAFETY: a live filter handle and NUL-terminated names.
        unsafe {
            (f.set_filter_bool)(filter.handle, c"hdr".as_ptr(), hdr);
            (f.set_filter_bool)(filter.handle, c"cleanAux".as_ptr(), clean_aux);
            (f.set_filter_int)(filter.handle, c"quality".as_ptr(), quality);
            (f.commit_filter)(filter.handle);
        }
        self.check()?;
        // SAFETY: a committed filter over the images above.
        unsafe { (f.execute_filter)(filter.handle) };
        self.check()
    }
}

impl Drop for Oidn {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once.
        unsafe { (self.functions.release_device)(self.device) }
    }
}

/// A filter of the device; released when dropped.
struct Filter<'a> {
    oidn: &'a Oidn,
    handle: Handle,
}

impl Drop for Filter<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once.
        unsafe { (self.oidn.functions.release_filter)(self.handle) }
    }
}
