// The scene: its geometry (scene_geometry.h: triangle meshes, spheres, Bézier revolves under one
// BVH), materials, textures, lights, media, the camera and the world. Builder calls validate their
// input and throw std::invalid_argument naming the object and the field; `build()` makes what
// rendering reads from them (the BVH, the prepared lights, the media's copies and sums) and leaves
// the scene ready for rendering and ray casting.
#pragma once

#include "geometry/camera.h"
#include "math/rng.h"
#include "scene/bsdf.h"
#include "scene/light.h"
#include "scene/material.h"
#include "scene/medium.h"
#include "scene/scene_geometry.h"
#include "shading/texture.h"

#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace ppm {

// Ranges the builders accept (std::invalid_argument outside them). They keep
// every square, product and float32 sum of the render finite:
//   coordinates, sizes and distances up to 1e30 m (squares 1e60; the
//   observable universe is 9e26 m);
//   radii and light sizes from 1e-100 m (their squares stay normal doubles);
//   light power, irradiance and radiance up to 1e20 (W, W/m^2, W/(m^2 sr));
//   the largest gain of a colour above 1 over max_bounces scatterings up to
//   kMaxPhotonGain. Photons carry their share of the lights' total flux
//   (about 1, in float32; LightSampler::flux_unit is the total in double),
//   so the total itself may be anything a double holds: a sun over a 10 km
//   scene or a 1e-40 W light. A pass of up to 2^32 photons of share at most
//   1e25 on one hit point still sums below float32's 3.4e38.
constexpr double kMaxCoordinate = 1e30;
constexpr double kMinSize = 1e-100;
constexpr double kMaxPower = 1e20;
constexpr double kMaxPhotonGain = 1e25;

constexpr uint32_t kMaxObjectId = 1u << 24;  // objects a node program can tell apart
// The object id a world's node program is run for (its coordinates are the direction's): kept
// apart from the others, so that naming it costs no table of 2^24 objects.
constexpr uint32_t kWorldObject = kMaxObjectId - 1;

// What a hit point keeps of its surface, from which Scene::surface_point shades it again.
struct SurfaceRecord {
  Vec3 position, ng, ns, wo;  // ns: the shading normal, a normal map applied
  Vec2f uv;
  Vec3f smooth_normal;        // before the normal map; zero: none
  glm::vec4 tangent;          // xyz and the bitangent's sign; w = 0: none
  uint32_t material, object, primitive;
  LightPath path;             // the ray that found it
};

class Scene {
 public:
  Scene();
  ~Scene();
  Scene(Scene&&) noexcept;

  uint32_t add_material(Material m);
  // Material `index` becomes `m` (an edit of its values): the surfaces using it keep their BVH.
  void replace_material(uint32_t index, Material m);
  // Texels that cannot be an albedo (see UnusableTexel) are an error naming the
  // first one, or, with clear_unusable, stay black (Texture::unusable_texels).
  uint32_t add_texture(const std::string& name, Texture texture, bool clear_unusable = false);

  // ---- Geometry: checked here (material indices, emission), kept by geometry() (scene_geometry.h
  // says what each does). ----
  void add_mesh(const MeshInput& mesh);
  // Set before build() (a built scene builds again).
  void set_dynamic(bool dynamic);
  void set_geometry_layout(GeometryLayout layout);
  // Throws std::invalid_argument naming the mesh where it cannot, the scene unchanged.
  void replace_mesh(const MeshInput& mesh);
  // A built dynamic scene's build() then drops the object's subtree and keeps the others.
  size_t remove_object(uint32_t object);
  // `visibility`: the RayKinds that see the object (others pass through it), and
  // kHoldoutFlag for a Holdout object (a hole for camera rays, itself for others).
  void add_sphere(const std::string& name, const Vec3& center, double radius, uint32_t material,
                  uint32_t object_id, uint8_t visibility = kAllRayKinds);
  void add_bezier_revolve(const std::string& name, const std::vector<Vec2>& points, bool cubic_chain,
                          const Mat4& object_to_world, uint32_t material, uint32_t object_id,
                          uint8_t visibility = kAllRayKinds);

  void add_light(Light light);
  // Removes the lights add_light added (the world and emissive surfaces stay). The BVH is kept:
  // a scene whose lights alone change is built again in the time its lights take.
  void remove_lights();
  // Drops the textures from index `count` on (a world's, exported again after it): refused while a
  // material uses one. The world goes black until set again; the BVH is kept.
  void remove_textures_from(size_t count);
  void set_camera(const Camera& camera);
  // The world: a constant radiance, or an image (`texture`, an index from
  // add_texture) seen through the rotation `world_to_texture` and scaled by
  // `strength`. Either replaces the other. `visibility`: the RayKinds that see
  // it when they escape (its light on surfaces is not affected).
  // `max_bounces` as Light::max_bounces.
  void set_background(const Color& radiance, uint8_t visibility = kAllRayKinds, int max_bounces = 1024);
  void set_environment(uint32_t texture, const Mat4& world_to_texture, const Color& strength,
                       EnvironmentProjection projection, uint8_t visibility = kAllRayKinds, int max_bounces = 1024);
  // What camera rays see where they leave the scene, in place of the background (a world whose
  // Light Path tells camera rays apart): an equirectangular image times `strength`, lighting
  // nothing. set_background and set_environment clear it.
  void set_camera_background(uint32_t texture, const Color& strength);
  const Environment* camera_background() const { return camera_environment_.get(); }

  // Renderers read a scene from their own threads without locks, so while one
  // holds a Lease on it the builders refuse to change it (std::runtime_error).
  // Leases may be taken and dropped on any thread at once: the count is atomic.
  class Lease {
   public:
    explicit Lease(const Scene& scene) : scene_(scene) { scene_.leases_.count.fetch_add(1); }
    ~Lease() { scene_.leases_.count.fetch_sub(1); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;

   private:
    const Scene& scene_;
  };

  // Builds the BVH and prepares the lights. Idempotent; builders called after it rebuild what they
  // change (the lights and the world alone keep the BVH; a dynamic scene's replaced meshes refit it).
  void build();

  // For a built scene: throws std::invalid_argument naming the light whose
  // flux overflows a double, or the material whose colour above 1 could grow a
  // photon's share of the flux beyond kMaxPhotonGain over `max_bounces` scatterings.
  void check_energy_range(int max_bounces) const;
  bool built() const { return geometry_.built() && lights_built_; }

  // The built geometry and the ray queries rendering makes most (SceneGeometry's).
  const SceneGeometry& geometry() const { return geometry_; }
  bool intersect(const Ray& ray, Hit& hit, double tmax = kInf) const { return geometry_.intersect(ray, hit, tmax); }
  void intersect_many(const Ray* rays, size_t count, Hit* hits) const { geometry_.intersect_many(rays, count, hits); }
  bool interleaves_walks() const { return geometry_.interleaves_walks(); }
  bool occluded(const Ray& ray, double distance) const { return geometry_.occluded(ray, distance); }
  bool is_holdout(const Hit& hit) const { return geometry_.is_holdout(hit); }
  double offset_floor() const { return geometry_.offset_floor(); }  // see ray_offset()

  // The surface at a hit seen from direction `wo` (its material's program run there); `footprint`:
  // the world size of a pixel there, for a camera ray (a Bump node's steps), else 0.
  // `path`: the ray that found it (the Light Path node).
  SurfacePoint surface_point(const Hit& hit, const Vec3& wo, double footprint = 0.0,
                             const LightPath& path = kCameraPath) const;
  // The emitted radiance where `hit` is (its material's textured emission evaluated there).
  Color emission(const Hit& hit, const Vec3& wo, const LightPath& path = kCameraPath) const;
  // The same from what a hit point keeps.
  SurfacePoint surface_point(const SurfaceRecord& record) const;
  // Where node programs see `hit` (Blender's Geometry and Texture Coordinate nodes).
  ShadingContext shading_context(const Hit& hit, const Vec3& wo, double footprint = 0.0,
                                 const LightPath& path = kCameraPath) const;
  // What node programs know of an object (Texture Coordinate's Object and Generated, Object Info);
  // objects never described are at the origin, unscaled, with generated = (object + 1) / 2.
  void set_object_info(uint32_t object, const ObjectInfo& info);
  const ObjectInfo& object_info(uint32_t object) const;
  // Voxel grids (a smoke domain's density, colour, ...), which object infos hold by slot
  // (ObjectInfo::grids); returns the grid's index for grid().
  uint32_t add_grid(std::shared_ptr<const VoxelGrid> grid);
  std::shared_ptr<const VoxelGrid> grid(uint32_t index) const;  // std::out_of_range beyond
  size_t grid_count() const { return grids_.size(); }

  // ---- Participating media (scene/medium.h; scene_media.cpp). ----
  // Validates (std::invalid_argument naming the medium and field: NaN, Inf, negative, a coefficient
  // above kMaxCoefficient or emission above kMaxPower) and returns the medium's index.
  uint32_t add_medium(Medium medium);
  // The medium filling space outside meshes with media; -1: none.
  void set_world_medium(int medium);
  // Material `material` carries medium `medium` (-1: none) inside; `surface` false: a boundary only.
  void set_material_medium(uint32_t material, int medium, bool surface);
  int world_medium() const { return world_medium_; }
  // The media added (by index), then from added_media() on the copies build() made of those that
  // vary, one per object bounding each (medium_in).
  const std::vector<Medium>& media() const { return media_; }
  size_t added_media() const { return added_media_; }
  // Medium `id`: one added, or from media().size() on one of their sums (overlapping media, below).
  const Medium& medium(uint32_t id) const {
    return id < media_.size() ? media_[id] : combined_media_[id - media_.size()].medium;
  }
  int32_t medium_index(const Medium* m) const {  // of a medium medium_of returned
    if (m >= media_.data() && m < media_.data() + media_.size()) return static_cast<int32_t>(m - media_.data());
    for (size_t k = 0; k < combined_media_.size(); ++k)
      if (m == &combined_media_[k].medium) return static_cast<int32_t>(media_.size() + k);
    return -1;
  }
  // Whether any path can be in a medium: the world has one or a material does. Scenes without pay
  // nothing: every media step is behind this test, once per pass or per path.
  bool has_media() const;
  bool has_mesh_media() const;  // a material carries a medium (a mesh bounds it)
  // The medium a path with `stack` is in (nullptr: none). Where the stack holds several media, or
  // one inside the world's, their sum, as Cycles adds the volumes on its stack, the world's among
  // them (combined_medium).
  const Medium* medium_of(const MediumStack& stack) const {
    if (stack.count + (world_medium_ >= 0) > 1 && !combined_media_.empty()) return combined_medium(stack);
    const int id = stack.top(world_medium_);
    return id >= 0 ? &media_[static_cast<size_t>(id)] : nullptr;
  }
  // The medium inside `material` on `object`: the material's, or where that varies in space the
  // object's copy of it (a copy per object: the field reads the object's coordinates); -1: none.
  int medium_in(uint32_t material, uint32_t object) const {
    const int id = materials_[material].medium;
    if (id < 0 || !media_[static_cast<size_t>(id)].field) return id;
    const auto found = copy_of_.find({id, object});
    return found != copy_of_.end() ? found->second : id;
  }
  // Whether media that vary get majorant grids where they pay (shading/majorant_grid.h; on by
  // default; off: one majorant per medium, as before them). Set before build().
  void set_majorant_grids(bool on);
  bool majorant_grids() const { return majorant_grids_; }
  // A medium's coefficients at `x` for a path travelling along `direction` (Cycles' volume shading
  // point: its normal and incoming direction face back along the ray).
  // `voxel_random` (not 0): an LCG seed for stochastic grids' voxel picks (ShadingContext).
  LocalMedium local_medium(const Medium& m, const Vec3& x, const Vec3& direction, uint32_t voxel_random = 0) const;
  // Its sigma_s alone: the constant where the medium does not vary (no program run).
  Color sigma_s_at(const Medium& m, const Vec3& x, const Vec3& direction) const {
    return m.varies() ? local_medium(m, x, direction).sigma_s : m.c.sigma_s;
  }
  // A medium that varies, along `ray` over (0, segment): free_path.h's track_segment, its
  // coefficients local_medium's along the ray, against the medium's majorant. `sums_emission`: the
  // caller reads TrackedSegment::emitted (an eye ray), for which a glow takes more collisions.
  TrackedSegment track(const Medium& m, const Ray& ray, double segment, const Color& throughput, bool may_scatter,
                       bool sums_emission, Rng& rng) const;
  // A path travelling along `direction` crosses the surface at `hit` (refracted, transmitted or a
  // boundary only): its stack enters or leaves the material's medium by the side it came from.
  void cross(const Hit& hit, const Vec3& direction, MediumStack& stack) const {
    const int id = medium_in(hit.material, hit.object);
    if (id < 0) return;
    if (glm::dot(direction, hit.geometric_normal) < 0.0)
      stack.enter(id);
    else
      stack.leave(id);
  }
  // The mesh media a point is inside (the world's is not on a stack), the innermost on top: by rays
  // from it along three directions, each counting the boundaries of each medium it leaves and
  // enters (a medium holds the point if two of the three leave it more than they enter). For paths
  // that start somewhere other than a surface: the camera, a light inside a fog box. Built scene.
  // `ray_kind`: the rays that will start there (what they see of objects hidden from some rays).
  MediumStack media_at(const Vec3& p, uint8_t ray_kind = kCameraRay) const;
  // The media the camera is in (media_at its position), set by build().
  const MediumStack& camera_media() const { return camera_media_; }
  // The media a camera ray starting at `origin` is in (its origin is on the near clip plane, on the
  // lens or in an orthographic window, as Cycles starts its rays): the camera's, changed by the
  // boundaries between the camera's position and `origin`, where build() found that a medium's box
  // reaches where rays start; else the camera's. Built scene.
  MediumStack camera_ray_media(const Vec3& origin) const {
    return rays_start_near_media_ ? media_along(camera_media_, camera_.position(), origin) : camera_media_;
  }
  // `stack` carried from `from` to `to` across the boundaries of media between them (those rays of
  // `ray_kind` meet).
  MediumStack media_along(MediumStack stack, const Vec3& from, const Vec3& to, uint8_t ray_kind = kCameraRay) const;
  // What arrives along a shadow ray over (0, distance) through media: the transmittance of each
  // medium it crosses (boundaries only are crossed, with the stack), 0 where a surface is in the way.
  // Through media that vary, an unbiased estimate (ratio tracking, with `rng`).
  Color shadow_transmittance(const Ray& ray, double distance, MediumStack stack, Rng& rng) const;

  // ---- Emitting media as lights (medium_lights.cpp). ----
  // The region of an emitting medium: the triangles of one object whose material carries it,
  // closed. Each is a light of kind Medium (Light::region).
  struct MediumRegion {
    uint32_t object;
    int medium;
    Aabb box;
    double volume;  // enclosed, m^3 (mesh_volume.h)
  };
  const MediumRegion& medium_region(uint32_t region) const { return medium_regions_[region]; }
  // Is `p` inside region `region`: does a ray from p along `direction` cross the region's own
  // triangles an odd number of times? Any other geometry on the way is passed by.
  bool inside_medium_region(uint32_t region, const Vec3& p, const Vec3& direction) const;
  // A uniform point inside region `region`: uniform in its box until one is inside (each test
  // along a random direction). False after kRegionTries misses (a region far smaller than its box).
  bool sample_medium_region(uint32_t region, Rng& rng, Vec3& point) const;
  static constexpr int kRegionTries = 1024;
  // What prepare_lights left out, each a sentence for Renderer::stats()["skipped"]: an emitting
  // world medium, emitting regions that are open or enclose nothing.
  const std::vector<std::string>& light_notes() const { return light_notes_; }

  const Material& material(uint32_t id) const { return materials_[id]; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<Texture>& textures() const { return textures_; }
  const std::vector<Light>& lights() const { return lights_; }
  const Camera& camera() const { return camera_; }
  bool has_camera() const { return has_camera_; }
  Aabb bounds() const { return geometry_.bounds(); }
  // Geometry (primitives, their attributes, the BVH), textures, materials and lights.
  size_t memory_bytes() const;

 private:
  void check_material(uint32_t material, const std::string& what) const;
  void check_new_material(Material& m) const;  // validates and completes a material to be stored
  void check_not_emissive(uint32_t material, const std::string& what) const;
  void check_lobes(Material& m, const std::string& what) const;
  std::vector<double> check_inputs(const Material& m, const std::string& what) const;
  void textured_emission(const Material& m, uint32_t triangle, Light& l) const;
  void invalidate_lights();
  void prepare_lights();
  void place_lights_in_media();  // each light's Light::media and straddles_media
  bool crosses_medium_boundary(const Aabb& box) const;
  void prepare_medium_lights(const Aabb& light_bounds);
  void ensure_mutable() const;
  std::vector<Material> materials_;
  std::vector<Medium> media_;
  int world_medium_ = -1;
  MediumStack camera_media_;
  // Overlapping media: the sums build() made (combine_overlapping_media), each with the media it
  // adds, ascending; with a world medium, each mesh medium and each sum also with the world's. A
  // stack whose media have none is in its innermost medium alone.
  struct CombinedMedium {
    Medium medium;
    int16_t ids[kMaxMediumStack] = {};
    uint8_t count = 0;
  };
  std::vector<CombinedMedium> combined_media_;
  const Medium* combined_medium(const MediumStack& stack) const;
  void combine_overlapping_media();
  size_t added_media_ = 0;  // media_ beyond these are copies (medium_in), remade by build()
  std::map<std::pair<int, uint32_t>, int> copy_of_;  // (medium added, object) -> its copy
  void prepare_media();  // the copies of media that vary, media_boxes_, then the sums (build)
  void copy_varying_media();
  // The box of each (object, medium)'s primitives: the material's medium, or with `copies` the
  // object's copy of it (medium_in).
  std::map<std::pair<uint32_t, int>, Aabb> medium_boxes(bool copies) const;
  std::map<std::pair<uint32_t, int>, Aabb> media_boxes_;  // medium_boxes(true) at the last prepare_media
  std::array<double, kMaxFieldOutputs> field_output_bounds(const Medium& copy, const Aabb& box) const;
  void bound_field(Medium& copy, const Aabb& box) const;
  void bound_field_per_cell(Medium& copy, const Aabb& box, const std::array<double, kMaxFieldOutputs>& bound) const;
  bool majorant_grids_ = true;
  bool camera_media_placed_ = false;
  bool rays_start_near_media_ = false;  // camera_ray_media: a medium's box reaches where rays start
  void place_camera_in_media();
  std::vector<Texture> textures_;
  SceneGeometry geometry_;
  std::vector<ObjectInfo> objects_;  // by object id (set_object_info)
  std::vector<std::shared_ptr<const VoxelGrid>> grids_;  // add_grid's
  ObjectInfo world_object_;          // kWorldObject's
  std::vector<Light> user_lights_;
  std::vector<Light> lights_;  // user lights + background + emissive triangles + emitting media, prepared
  std::vector<MediumRegion> medium_regions_;
  std::vector<std::string> light_notes_;
  Color background_{0.0};
  struct EnvironmentInput {
    uint32_t texture;
    Mat3 world_to_texture;
    Color strength;
    EnvironmentProjection projection;
  };
  std::unique_ptr<EnvironmentInput> environment_input_;  // null: the constant background_
  std::unique_ptr<Environment> environment_;             // built from it
  std::unique_ptr<EnvironmentInput> camera_environment_input_;
  std::unique_ptr<Environment> camera_environment_;
  uint8_t background_visibility_ = kAllRayKinds;
  int background_max_bounces_ = 1024;
  Camera camera_;
  bool has_camera_ = false;

  bool lights_built_ = false;    // lights_ and the environments
  // The leases on this scene. Movable so that Scene is (a leased scene is never moved: its
  // renderers hold it by shared_ptr).
  struct LeaseCount {
    std::atomic<int> count{0};
    LeaseCount() = default;
    LeaseCount(LeaseCount&& other) noexcept : count(other.count.load()) {}
  };
  mutable LeaseCount leases_;
};

}  // namespace ppm
