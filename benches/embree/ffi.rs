//! The part of the Embree 3 C API (`embree3/rtcore*.h`, version 3.13) this bench uses,
//! declared by hand: a device, a scene of triangle meshes, sphere points, cone curves
//! and user geometry with its callbacks, and the single-ray and 16-ray queries. The
//! layouts follow the headers as Debian's `libembree-dev` 3.13.5 configures them:
//! `RTC_MAX_INSTANCE_LEVEL_COUNT` 1 and `RTC_MIN_WIDTH` 0 (`rtcore_config.h`), so the
//! intersection context has no instance
//! stack size and no minimum-width factor.

#![allow(non_camel_case_types, dead_code)]

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `RTCDevice` (opaque handle).
pub type RTCDevice = *mut c_void;
/// `RTCScene` (opaque handle).
pub type RTCScene = *mut c_void;
/// `RTCGeometry` (opaque handle).
pub type RTCGeometry = *mut c_void;

/// `RTC_INVALID_GEOMETRY_ID`.
pub const RTC_INVALID_GEOMETRY_ID: c_uint = u32::MAX;

/// `enum RTCGeometryType` (the members used).
pub const RTC_GEOMETRY_TYPE_TRIANGLE: c_int = 0;
/// Cone segments with flat caps, no joints between segments.
pub const RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE: c_int = 15;
/// Spheres given as points with a radius.
pub const RTC_GEOMETRY_TYPE_SPHERE_POINT: c_int = 50;
/// Primitives defined by the application's bounds, intersect and occluded callbacks.
pub const RTC_GEOMETRY_TYPE_USER: c_int = 120;

/// `enum RTCBufferType`.
pub const RTC_BUFFER_TYPE_INDEX: c_int = 0;
/// `enum RTCBufferType`.
pub const RTC_BUFFER_TYPE_VERTEX: c_int = 1;

/// `enum RTCFormat`: `RTC_FORMAT_UINT`.
pub const RTC_FORMAT_UINT: c_int = 0x5001;
/// `RTC_FORMAT_UINT3`.
pub const RTC_FORMAT_UINT3: c_int = 0x5003;
/// `RTC_FORMAT_FLOAT3`.
pub const RTC_FORMAT_FLOAT3: c_int = 0x9003;
/// `RTC_FORMAT_FLOAT4`.
pub const RTC_FORMAT_FLOAT4: c_int = 0x9004;

/// `enum RTCSceneFlags`: the robust build and traversal mode.
pub const RTC_SCENE_FLAG_ROBUST: c_int = 1 << 2;
/// `enum RTCIntersectContextFlags`.
pub const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: c_int = 0;
/// `enum RTCIntersectContextFlags`.
pub const RTC_INTERSECT_CONTEXT_FLAG_COHERENT: c_int = 1;

/// `enum RTCError`: `RTC_ERROR_NONE`.
pub const RTC_ERROR_NONE: c_int = 0;

/// `struct RTCIntersectContext`.
#[repr(C)]
pub struct RTCIntersectContext {
    /// Coherent or incoherent rays.
    pub flags: c_int,
    /// Filter callback (none).
    pub filter: Option<unsafe extern "C" fn(*const c_void)>,
    /// Instance id stack.
    pub inst_id: [c_uint; 1],
}

impl RTCIntersectContext {
    /// What the header's inline `rtcInitIntersectContext` does, with the given flags.
    pub fn new(flags: c_int) -> Self {
        Self {
            flags,
            filter: None,
            inst_id: [RTC_INVALID_GEOMETRY_ID],
        }
    }
}

/// `struct RTCRay`.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay {
    pub org_x: f32,
    pub org_y: f32,
    pub org_z: f32,
    pub tnear: f32,
    pub dir_x: f32,
    pub dir_y: f32,
    pub dir_z: f32,
    pub time: f32,
    pub tfar: f32,
    pub mask: c_uint,
    pub id: c_uint,
    pub flags: c_uint,
}

/// `struct RTCHit`.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit {
    pub ng_x: f32,
    pub ng_y: f32,
    pub ng_z: f32,
    pub u: f32,
    pub v: f32,
    pub prim_id: c_uint,
    pub geom_id: c_uint,
    pub inst_id: [c_uint; 1],
}

/// `struct RTCRayHit`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit {
    pub ray: RTCRay,
    pub hit: RTCHit,
}

/// `struct RTCRay16`.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay16 {
    pub org_x: [f32; 16],
    pub org_y: [f32; 16],
    pub org_z: [f32; 16],
    pub tnear: [f32; 16],
    pub dir_x: [f32; 16],
    pub dir_y: [f32; 16],
    pub dir_z: [f32; 16],
    pub time: [f32; 16],
    pub tfar: [f32; 16],
    pub mask: [c_uint; 16],
    pub id: [c_uint; 16],
    pub flags: [c_uint; 16],
}

/// `struct RTCHit16`.
#[repr(C, align(64))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit16 {
    pub ng_x: [f32; 16],
    pub ng_y: [f32; 16],
    pub ng_z: [f32; 16],
    pub u: [f32; 16],
    pub v: [f32; 16],
    pub prim_id: [c_uint; 16],
    pub geom_id: [c_uint; 16],
    pub inst_id: [[c_uint; 16]; 1],
}

/// `struct RTCRayHit16`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit16 {
    pub ray: RTCRay16,
    pub hit: RTCHit16,
}

/// `struct RTCBounds` (`rtcore_common.h`).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCBounds {
    pub lower_x: f32,
    pub lower_y: f32,
    pub lower_z: f32,
    pub align0: f32,
    pub upper_x: f32,
    pub upper_y: f32,
    pub upper_z: f32,
    pub align1: f32,
}

/// `struct RTCBoundsFunctionArguments` (`rtcore_geometry.h`).
#[repr(C)]
pub struct RTCBoundsFunctionArguments {
    /// The geometry's user data.
    pub geometry_user_ptr: *mut c_void,
    pub prim_id: c_uint,
    pub time_step: c_uint,
    /// Where the callback writes the bounds.
    pub bounds_o: *mut RTCBounds,
}

/// `struct RTCIntersectFunctionNArguments` (`rtcore_geometry.h`).
#[repr(C)]
pub struct RTCIntersectFunctionNArguments {
    /// `N` entries: -1 for an active ray, 0 for an inactive one.
    pub valid: *mut c_int,
    /// The pointer given to `rtcSetGeometryUserData`.
    pub geometry_user_ptr: *mut c_void,
    pub prim_id: c_uint,
    pub context: *mut RTCIntersectContext,
    /// `struct RTCRayHitN*`: `N` rays and hits, structure of arrays.
    pub rayhit: *mut c_void,
    pub n: c_uint,
    pub geom_id: c_uint,
}

/// `struct RTCOccludedFunctionNArguments` (`rtcore_geometry.h`).
#[repr(C)]
pub struct RTCOccludedFunctionNArguments {
    /// `N` entries: -1 for an active ray, 0 for an inactive one.
    pub valid: *mut c_int,
    /// The pointer given to `rtcSetGeometryUserData`.
    pub geometry_user_ptr: *mut c_void,
    pub prim_id: c_uint,
    pub context: *mut RTCIntersectContext,
    /// `struct RTCRayN*`: `N` rays, structure of arrays.
    pub ray: *mut c_void,
    pub n: c_uint,
    pub geom_id: c_uint,
}

/// `RTCBoundsFunction`.
pub type RTCBoundsFunction = unsafe extern "C" fn(args: *const RTCBoundsFunctionArguments);
/// `RTCIntersectFunctionN`.
pub type RTCIntersectFunctionN = unsafe extern "C" fn(args: *const RTCIntersectFunctionNArguments);
/// `RTCOccludedFunctionN`.
pub type RTCOccludedFunctionN = unsafe extern "C" fn(args: *const RTCOccludedFunctionNArguments);

// Checked against the C layouts: sizes and the offsets that differ between packings.
const _: () = {
    assert!(std::mem::size_of::<RTCRay>() == 48);
    assert!(std::mem::size_of::<RTCHit>() == 32);
    assert!(std::mem::size_of::<RTCRayHit>() == 80);
    assert!(std::mem::size_of::<RTCRay16>() == 768);
    assert!(std::mem::size_of::<RTCHit16>() == 512);
    assert!(std::mem::size_of::<RTCRayHit16>() == 1280);
    assert!(std::mem::size_of::<RTCIntersectContext>() == 24);
    assert!(std::mem::offset_of!(RTCIntersectContext, filter) == 8);
    assert!(std::mem::size_of::<RTCBounds>() == 32);
    assert!(std::mem::size_of::<RTCBoundsFunctionArguments>() == 24);
    assert!(std::mem::offset_of!(RTCBoundsFunctionArguments, bounds_o) == 16);
    assert!(std::mem::size_of::<RTCIntersectFunctionNArguments>() == 48);
    assert!(std::mem::offset_of!(RTCIntersectFunctionNArguments, context) == 24);
    assert!(std::mem::offset_of!(RTCIntersectFunctionNArguments, n) == 40);
    assert!(std::mem::size_of::<RTCOccludedFunctionNArguments>() == 48);
    assert!(std::mem::offset_of!(RTCOccludedFunctionNArguments, ray) == 32);
    // The structure-of-arrays view of the user-geometry callbacks
    // (`benches/support/user_spheres.rs`): ray fields, then hit fields, 32-bit words.
    assert!(std::mem::offset_of!(RTCRayHit, hit) == 12 * 4);
    assert!(std::mem::offset_of!(RTCRayHit16, hit) == 12 * 16 * 4);
    assert!(std::mem::offset_of!(RTCRay, tfar) == 8 * 4);
    assert!(std::mem::offset_of!(RTCHit16, inst_id) == 7 * 16 * 4);
};

#[link(name = "embree3")]
extern "C" {
    pub fn rtcNewDevice(config: *const c_char) -> RTCDevice;
    pub fn rtcReleaseDevice(device: RTCDevice);
    pub fn rtcGetDeviceError(device: RTCDevice) -> c_int;
    pub fn rtcNewScene(device: RTCDevice) -> RTCScene;
    pub fn rtcReleaseScene(scene: RTCScene);
    pub fn rtcSetSceneFlags(scene: RTCScene, flags: c_int);
    pub fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> c_uint;
    pub fn rtcCommitScene(scene: RTCScene);
    pub fn rtcNewGeometry(device: RTCDevice, kind: c_int) -> RTCGeometry;
    pub fn rtcReleaseGeometry(geometry: RTCGeometry);
    pub fn rtcCommitGeometry(geometry: RTCGeometry);
    pub fn rtcSetNewGeometryBuffer(
        geometry: RTCGeometry,
        kind: c_int,
        slot: c_uint,
        format: c_int,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    pub fn rtcSetGeometryUserPrimitiveCount(geometry: RTCGeometry, count: c_uint);
    pub fn rtcSetGeometryUserData(geometry: RTCGeometry, ptr: *mut c_void);
    pub fn rtcSetGeometryBoundsFunction(
        geometry: RTCGeometry,
        bounds: Option<RTCBoundsFunction>,
        user_ptr: *mut c_void,
    );
    pub fn rtcSetGeometryIntersectFunction(
        geometry: RTCGeometry,
        intersect: Option<RTCIntersectFunctionN>,
    );
    pub fn rtcSetGeometryOccludedFunction(
        geometry: RTCGeometry,
        occluded: Option<RTCOccludedFunctionN>,
    );
    pub fn rtcIntersect1(
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        rayhit: *mut RTCRayHit,
    );
    pub fn rtcOccluded1(scene: RTCScene, context: *mut RTCIntersectContext, ray: *mut RTCRay);
    pub fn rtcIntersect16(
        valid: *const c_int,
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        rayhit: *mut RTCRayHit16,
    );
}
