//! The frame report: what a frame did, on which device, and what it cost on the GPU.

use crate::frame::timing::PassReport;
use crate::plan::{FramePlan, LightPlan};
use crate::shadow_map::ShadowMapSettings;
use crate::shadow_volume::ShadowVolumeSettings;
use serde::Serialize;
use umbra_scene::{Adjacency, Scene, TopologyReport};
use umbra_vk::Capabilities;

/// The scene a frame rendered, in numbers.
#[derive(Clone, Debug, Serialize)]
pub struct SceneSummary {
    /// Scene name.
    pub name: String,
    /// Placed objects.
    pub objects: usize,
    /// Distinct meshes.
    pub meshes: usize,
    /// Triangles per full-scene pass.
    pub triangles: usize,
    /// Lights in the scene (recorded or not).
    pub lights: usize,
    /// Per mesh: is it closed, its boundary and non-manifold edges, and what shadow volumes
    /// do about them.
    pub topology: Vec<MeshTopology>,
}

impl SceneSummary {
    /// Summarises `scene`; `adjacency[i]` is mesh `i`'s welded connectivity.
    pub fn of(scene: &Scene, adjacency: &[std::sync::Arc<Adjacency>]) -> Self {
        let topology = scene
            .meshes
            .iter()
            .zip(adjacency)
            .enumerate()
            .map(|(i, (mesh, adj))| {
                let casters = scene.objects.iter().filter(|o| o.mesh == i && o.casts_shadows).count();
                MeshTopology::of(i, mesh, adj.report, casters)
            })
            .collect();
        Self {
            name: scene.name.clone(),
            objects: scene.objects.len(),
            meshes: scene.meshes.len(),
            triangles: scene.triangle_count(),
            lights: scene.lights.len(),
            topology,
        }
    }
}

/// Where a mesh's topology counts come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TopologySource {
    /// The source file's triangle list as authored (an edge is one vertex-index pair), before
    /// any unwelding for flat normals: glTF meshes.
    AsAuthored,
    /// The mesh as built, vertices welded by exact position: procedural and inline meshes.
    Welded,
}

/// How shadow volumes treat a mesh (decided on its welded connectivity).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumeConstruction {
    /// A closed 2-manifold: front cap = light-facing triangles, back cap = the others at
    /// infinity, silhouette edges extruded (Everitt–Kilgard).
    SilhouetteExtrusion,
    /// Open or non-manifold: every triangle casts, oriented towards the light and closed on its
    /// own, and each edge is extruded by its net multiplicity, so holes and edges shared by
    /// three or more faces leave no crack and no inverted shadow.
    PerTriangle,
}

/// One mesh's topology as the frame report lists it.
#[derive(Clone, Debug, Serialize)]
pub struct MeshTopology {
    /// Mesh index in the scene.
    pub mesh: usize,
    /// Mesh name.
    pub name: String,
    /// Triangles.
    pub triangles: usize,
    /// No boundary and no non-manifold edge (counted as [`MeshTopology::counted`] says).
    pub closed: bool,
    /// Edges used by one face.
    pub boundary_edges: usize,
    /// Edges used by three or more faces.
    pub non_manifold_edges: usize,
    /// Where the three counts above come from.
    pub counted: TopologySource,
    /// After welding by exact position: what shadow volumes and silhouette maps use.
    pub welded: TopologyReport,
    /// Objects using this mesh that cast shadows.
    pub casters: usize,
    /// What shadow volumes do with it.
    pub shadow_volumes: VolumeConstruction,
}

impl MeshTopology {
    /// The entry of mesh `index`, whose welded report is `welded`.
    pub fn of(index: usize, mesh: &umbra_scene::Mesh, welded: TopologyReport, casters: usize) -> Self {
        let (counts, counted) = match mesh.authored_topology {
            Some(authored) => (authored, TopologySource::AsAuthored),
            None => (welded, TopologySource::Welded),
        };
        Self {
            mesh: index,
            name: mesh.name.clone(),
            triangles: counts.triangles,
            closed: counts.closed,
            boundary_edges: counts.boundary_edges,
            non_manifold_edges: counts.non_manifold_edges,
            counted,
            welded,
            casters,
            shadow_volumes: if welded.closed {
                VolumeConstruction::SilhouetteExtrusion
            } else {
                VolumeConstruction::PerTriangle
            },
        }
    }

    /// A one-line warning for a caster that is open or non-manifold (as counted or after
    /// welding), `None` for closed meshes and meshes no object casts from.
    pub fn warning(&self) -> Option<String> {
        if self.casters == 0 || (self.closed && self.welded.closed) {
            return None;
        }
        let mut what = Vec::new();
        if self.boundary_edges > 0 {
            what.push(format!("open ({} boundary edges)", self.boundary_edges));
        }
        if self.non_manifold_edges > 0 {
            what.push(format!(
                "non-manifold ({} non-manifold edge{})",
                self.non_manifold_edges,
                plural(self.non_manifold_edges)
            ));
        }
        let counted = match self.counted {
            TopologySource::AsAuthored => "as authored",
            TopologySource::Welded => "welded",
        };
        Some(format!(
            "warning: caster mesh {} {:?} is {} {counted}; after welding {} boundary, {} non-manifold edges: {}",
            self.mesh,
            self.name,
            if what.is_empty() { "closed".to_owned() } else { what.join(" and ") },
            self.welded.boundary_edges,
            self.welded.non_manifold_edges,
            match self.shadow_volumes {
                VolumeConstruction::SilhouetteExtrusion => "its shadow volumes extrude silhouette edges",
                VolumeConstruction::PerTriangle => {
                    "its shadow volumes close every triangle on its own (no crack, no inverted shadow)"
                }
            }
        ))
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// What one frame did. Serialises to JSON with [`FrameReport::to_json`].
#[derive(Clone, Debug, Serialize)]
pub struct FrameReport {
    /// Device name (same as `capabilities.device_name`).
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// The device's capabilities as umbra uses them.
    pub capabilities: Capabilities,
    /// The scene.
    pub scene: SceneSummary,
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// Shadow-map settings the renderer was built with.
    pub shadow_map_settings: ShadowMapSettings,
    /// Shadow-volume settings the renderer was built with.
    pub shadow_volume_settings: ShadowVolumeSettings,
    /// The frame plan in numbers: lights recorded, skipped and shadowed, casters culled per
    /// reason.
    pub plan: FramePlan,
    /// Per light: technique, passes recorded, what was culled and why, and its technique's
    /// figures.
    pub lights: Vec<LightPlan>,
    /// Every recorded pass, in order, with its GPU time.
    pub passes: Vec<PassReport>,
    /// Sum of the GPU times of the passes that make the image (`None` without timestamps);
    /// diagnostic passes are not included.
    pub total_gpu_ms: Option<f64>,
    /// Sum of the diagnostic passes' GPU times (0 when there were none).
    pub diagnostic_gpu_ms: Option<f64>,
    /// CPU wall time of the whole `render` call, in milliseconds: the sum of the three below
    /// plus reading back and reporting.
    pub cpu_frame_ms: f64,
    /// Of which checking, planning, preparing every light's technique on the CPU, uploading
    /// and binding.
    pub cpu_prepare_ms: f64,
    /// Of which declaring and recording the passes.
    pub cpu_record_ms: f64,
    /// Of which submitting and waiting for the GPU (every submission of the frame).
    pub cpu_submit_wait_ms: f64,
    /// Queue submissions this frame made: 1, or 2 when blocker culling read its queries back.
    pub submissions: u64,
    /// Bytes of mesh data (vertices and indices) uploaded for this frame: 0 when every mesh
    /// kept its revision since the frame before ([`umbra_scene::Mesh::touch`]).
    pub geometry_uploaded_bytes: u64,
    /// Device-memory allocations (buffers and images) the renderer made for this frame
    /// ([`umbra_vk::Context::memory_allocations`] across `render`).
    pub memory_allocations: u64,
}

impl FrameReport {
    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// Pass `id`, if recorded.
    pub fn pass(&self, id: crate::PassId) -> Option<&PassReport> {
        self.passes.iter().find(|p| p.id == id)
    }
}
