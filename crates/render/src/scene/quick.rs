//! A scene's quick preview: the same world, made in seconds.

use super::SceneDesc;

/// Terrain samples per side of a quick preview.
pub const QUICK_TERRAIN_SIZE: usize = 256;

/// Most stream-power, hydraulic and thermal erosion steps of a quick preview.
const QUICK_EROSION_STEPS: [u32; 3] = [5, 20, 5];

/// How much coarser a quick preview's cloud voxels and shadow cells are.
const QUICK_CLOUD_COARSENING: f32 = 4.0;

impl SceneDesc {
    /// The same world made quickly, for a preview (the examples' `--quick`)
    /// or a test: a terrain of more than [`QUICK_TERRAIN_SIZE`] samples a
    /// side keeps its extent on that many (its cells as much larger: the
    /// built-in scene's 2048 samples of 30 m become 256 of 240 m); erosion
    /// takes at most 5 stream-power, 20 hydraulic and 5 thermal steps; the
    /// clouds' voxels and shadow cells are 4 times coarser. The camera, the
    /// picture's size and its sampling are the caller's.
    ///
    /// A scene that was valid may not be afterwards: a terrain of
    /// 16 384 samples of 10 km would need cells of 640 km, beyond
    /// `terrain.cell_size_m`'s range, and [`SceneDesc::validate`] says so.
    ///
    /// ```
    /// use natura_render::SceneDesc;
    ///
    /// let full = SceneDesc::default();
    /// let quick = full.quick();
    /// assert_eq!(quick.terrain.size, 256);
    /// let extent = |s: &SceneDesc| s.terrain.size as f32 * s.terrain.cell_size_m;
    /// assert_eq!(extent(&quick), extent(&full));
    /// assert!(quick.erosion.hydraulic_steps <= 20);
    /// assert_eq!(quick.camera, full.camera);
    /// quick.validate().unwrap();
    /// ```
    #[must_use]
    pub fn quick(&self) -> SceneDesc {
        let mut s = self.clone();
        if s.terrain.size > QUICK_TERRAIN_SIZE {
            s.terrain.resample(QUICK_TERRAIN_SIZE);
        }
        let e = &mut s.erosion;
        let [stream_power, hydraulic, thermal] = QUICK_EROSION_STEPS;
        e.stream_power_steps = e.stream_power_steps.min(stream_power);
        e.hydraulic_steps = e.hydraulic_steps.min(hydraulic);
        e.thermal_steps = e.thermal_steps.min(thermal);
        s.clouds.voxel_m *= QUICK_CLOUD_COARSENING;
        s.clouds.shadow_cell_m *= QUICK_CLOUD_COARSENING;
        s
    }
}
