#include "render/offscreen_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/GraphicsContext>
#include <osg/MatrixTransform>
#include <osg/Program>
#include <osg/Shader>
#include <osg/Texture2D>
#include <osg/Uniform>
#include <osgViewer/Viewer>
#include <vector>

#include "render/textures.h"

namespace pwsim::render {
namespace {

/// An osg::GraphicsContext drawing into a BGRA buffer in memory through OSMesa (no window
/// system). Single-buffered: after swapBuffers (glFinish) the buffer holds the whole frame.
class OsmesaGraphicsContext final : public osg::GraphicsContext {
 public:
  explicit OsmesaGraphicsContext(osg::GraphicsContext::Traits* traits) {
    _traits = traits;
    setState(new osg::State);
    getState()->setGraphicsContext(this);
    getState()->setContextID(osg::GraphicsContext::createNewContextID());
  }
  bool valid() const override { return true; }
  bool realizeImplementation() override {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_BGRA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_STENCIL_BITS,
                              8,
                              OSMESA_ACCUM_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_COMPAT_PROFILE,
                              0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    buffer_.assign(static_cast<std::size_t>(_traits->width) * _traits->height * 4, 0);
    realized_ = context_ != nullptr;
    return realized_;
  }
  bool isRealizedImplementation() const override { return realized_; }
  void closeImplementation() override {
    if (context_ != nullptr) OSMesaDestroyContext(context_);
    context_ = nullptr;
    realized_ = false;
  }
  bool makeCurrentImplementation() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, _traits->width,
                           _traits->height)) {
      return false;
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 at the top, as images are stored
    return true;
  }
  bool makeContextCurrentImplementation(osg::GraphicsContext*) override {
    return makeCurrentImplementation();
  }
  bool releaseContextImplementation() override { return true; }
  void bindPBufferToTextureImplementation(GLenum) override {}
  void swapBuffersImplementation() override { glFinish(); }

  const std::uint8_t* pixels() const { return buffer_.data(); }
  std::uint8_t* mutable_pixels() { return buffer_.data(); }

 private:
  ~OsmesaGraphicsContext() override { closeImplementation(); }
  ::OSMesaContext context_{nullptr};
  std::vector<std::uint8_t> buffer_;
  bool realized_{false};
};

/// Eigen (column vectors) to OSG (row vectors): the same numbers, transposed; Eigen's
/// column-major storage read row by row is exactly that transpose.
osg::Matrixd ToOsg(const Eigen::Matrix4d& m) { return osg::Matrixd(m.data()); }

/// R_CG: the OpenGL eye axes (x right, y up, z backwards) expressed in C (x ahead, y left, z up).
Eigen::Matrix4d GlEyeInCamera() {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) << 0, 0, -1,  //
      -1, 0, 0,                     //
      0, 1, 0;
  return m;
}

/// A repeating texture, mip-mapped (the chain built from the image: a minified floor shows the
/// mean of its texels, not a beat of them against the pixel grid) and sampled with up to
/// `anisotropy` taps along the direction of strongest minification.
osg::ref_ptr<osg::Texture2D> MakeOsgTexture(TextureKind kind, std::uint32_t seed, int anisotropy) {
  const TextureImage texture = MakeTexture(kind, seed);
  auto* data = new unsigned char[texture.rgb.size()];
  std::memcpy(data, texture.rgb.data(), texture.rgb.size());
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->setImage(texture.size, texture.size, 1, GL_RGB, GL_RGB, GL_UNSIGNED_BYTE, data,
                  osg::Image::USE_NEW_DELETE);
  osg::ref_ptr<osg::Texture2D> out = new osg::Texture2D(image.get());
  out->setWrap(osg::Texture::WRAP_S, osg::Texture::REPEAT);
  out->setWrap(osg::Texture::WRAP_T, osg::Texture::REPEAT);
  out->setFilter(osg::Texture::MIN_FILTER, osg::Texture::LINEAR_MIPMAP_NEAREST);
  out->setFilter(osg::Texture::MAG_FILTER, osg::Texture::LINEAR);
  out->setMaxAnisotropy(static_cast<float>(anisotropy));  // GL clamps it to the context's maximum
  return out;
}

/// The fragment work is what llvmpipe spends its time on (≈ 85 % of a frame's CPU in JIT code),
/// so the quads are drawn with a minimal GLSL 1.30 program instead of Mesa's fixed-function
/// emulation: the colour is `flat` (it is constant per quad anyway, so nothing is interpolated
/// per pixel) and only two texture coordinates are interpolated, with no projective divide
/// (fixed function carries s, t, r, q and divides by q). The image is that of fixed function up
/// to a few edge pixels (mean difference 1e-4 of a level at 2×1440×1600).
constexpr const char* kVertexShader = R"(#version 130
out vec2 uv;
flat out vec4 colour;
void main() {
  gl_Position = ftransform();
  uv = gl_MultiTexCoord0.xy;
  colour = gl_Color;
}
)";
constexpr const char* kTexturedFragmentShader = R"(#version 130
uniform sampler2D tex;
in vec2 uv;
flat in vec4 colour;
void main() { gl_FragColor = texture(tex, uv) * colour; }
)";
constexpr const char* kPlainFragmentShader = R"(#version 130
flat in vec4 colour;
void main() { gl_FragColor = colour; }
)";

osg::ref_ptr<osg::Program> MakeProgram(bool textured) {
  osg::ref_ptr<osg::Program> program = new osg::Program;
  program->addShader(new osg::Shader(osg::Shader::VERTEX, kVertexShader));
  program->addShader(new osg::Shader(osg::Shader::FRAGMENT,
                                     textured ? kTexturedFragmentShader : kPlainFragmentShader));
  return program;
}

/// One Geode per frame of reference; quads of one texture share one Geometry. Lighting is off:
/// a fixed shade per quad (from its normal and the scene's light direction) is baked into the
/// vertex colours, so pixels do not change when the camera moves (good for optical flow).
osg::ref_ptr<osg::Geode> MakeGeode(const std::vector<Quad>& quads, const RenderScene& scene,
                                   int anisotropy) {
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  std::map<TextureKind, std::vector<const Quad*>> by_texture;
  for (const Quad& quad : quads) by_texture[quad.texture].push_back(&quad);
  const Eigen::Vector3d light = scene.light_dir_W.normalized();
  for (const auto& [kind, group] : by_texture) {
    osg::ref_ptr<osg::Geometry> geometry = new osg::Geometry;
    osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
    osg::ref_ptr<osg::Vec4Array> colors = new osg::Vec4Array;
    osg::ref_ptr<osg::Vec2Array> uvs = new osg::Vec2Array;
    for (const Quad* quad : group) {
      const double shade = 0.70 + 0.30 * std::abs(QuadNormal(*quad).dot(light));
      const Eigen::Vector3d u_axis = quad->corners[1] - quad->corners[0];
      const Eigen::Vector3d v_axis = quad->corners[3] - quad->corners[0];
      const double u_len = u_axis.norm() > 0 ? u_axis.norm() : 1.0;
      const double v_len = v_axis.norm() > 0 ? v_axis.norm() : 1.0;
      for (const Eigen::Vector3d& corner : quad->corners) {
        vertices->push_back(osg::Vec3(static_cast<float>(corner.x()),
                                      static_cast<float>(corner.y()),
                                      static_cast<float>(corner.z())));
        const Eigen::Vector3d d = corner - quad->corners[0];
        uvs->push_back(quad->world_uv ? osg::Vec2(static_cast<float>(corner.x() / quad->tile),
                                                  static_cast<float>(corner.y() / quad->tile))
                                      : osg::Vec2(static_cast<float>(d.dot(u_axis) / u_len / quad->tile),
                                                  static_cast<float>(d.dot(v_axis) / v_len / quad->tile)));
        colors->push_back(osg::Vec4(static_cast<float>(quad->color.r * shade),
                                    static_cast<float>(quad->color.g * shade),
                                    static_cast<float>(quad->color.b * shade), 1.0F));
      }
    }
    geometry->setVertexArray(vertices.get());
    geometry->setColorArray(colors.get(), osg::Array::BIND_PER_VERTEX);
    geometry->setTexCoordArray(0, uvs.get());
    geometry->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, static_cast<int>(vertices->size())));
    osg::StateSet* state = geometry->getOrCreateStateSet();
    const bool textured = kind != TextureKind::kNone;
    state->setAttributeAndModes(MakeProgram(textured).get(), osg::StateAttribute::ON);
    if (textured) {
      state->setTextureAttributeAndModes(0, MakeOsgTexture(kind, scene.texture_seed, anisotropy).get(),
                                         osg::StateAttribute::ON);
      state->addUniform(new osg::Uniform("tex", 0));
    }
    geode->addDrawable(geometry.get());
  }
  geode->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
  return geode;
}

osg::Matrixd EyeProjection(const EyeFov& fov, bool left_eye, double near, double far) {
  constexpr double kDeg = M_PI / 180.0;
  const double left = (left_eye ? fov.outer_deg : fov.inner_deg) * kDeg;
  const double right = (left_eye ? fov.inner_deg : fov.outer_deg) * kDeg;
  return ToOsg(FrustumProjection(left, right, fov.down_deg * kDeg, fov.up_deg * kDeg, near, far));
}

}  // namespace

Eigen::Matrix4d FrustumProjection(double left, double right, double down, double up, double near,
                                  double far) {
  const double l = -near * std::tan(left), r = near * std::tan(right);
  const double b = -near * std::tan(down), t = near * std::tan(up);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = 2 * near / (r - l);
  p(0, 2) = (r + l) / (r - l);
  p(1, 1) = 2 * near / (t - b);
  p(1, 2) = (t + b) / (t - b);
  p(2, 2) = -(far + near) / (far - near);
  p(2, 3) = -2 * far * near / (far - near);
  p(3, 2) = -1;
  return p;
}

struct OffscreenRenderer::Impl {
  RenderConfig config;
  osg::ref_ptr<OsmesaGraphicsContext> gc;
  osgViewer::Viewer viewer;
  osg::ref_ptr<osg::MatrixTransform> chair;
  std::string renderer;
  std::string version;
  bool warmed_up{false};
  std::vector<osg::Camera*> clearing;  ///< the cameras that clear: master (mono) or the eyes
  Eigen::Vector3d room_min_W, room_max_W;
  double eye_margin{0.0};  ///< [m] how far inside the room the head must be to skip the clear
  double anisotropy{1.0};  ///< texture anisotropy in effect (config's, clamped by the context)
};

OffscreenRenderer::OffscreenRenderer(const RenderScene& scene, const RenderConfig& config)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.config = config;
  d.room_min_W = scene.room_min_W;
  d.room_max_W = scene.room_max_W;
  // The near plane's corners lie within 0.25 m of the eye for any field of view under ±75°;
  // the stereo eyes are ipd/2 off the head.
  d.eye_margin = 0.25 + (config.stereo ? 0.5 * config.hmd.ipd : 0.0);
  const int width = config.image_width(), height = config.image_height();

  osg::ref_ptr<osg::GraphicsContext::Traits> traits = new osg::GraphicsContext::Traits;
  traits->width = width;
  traits->height = height;
  traits->doubleBuffer = false;
  traits->pbuffer = true;
  d.gc = new OsmesaGraphicsContext(traits.get());

  // The scene graph: room and cushion in W, the chair under its pose X_WV.
  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->addChild(MakeGeode(scene.world, scene, config.anisotropy).get());
  d.chair = new osg::MatrixTransform;
  d.chair->addChild(MakeGeode(scene.chair, scene, config.anisotropy).get());
  root->addChild(d.chair.get());

  osgViewer::Viewer& viewer = d.viewer;
  viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);  // OSMesa: one thread
  viewer.setKeyEventSetsDone(0);
  osg::Camera* master = viewer.getCamera();
  master->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  const osg::Vec4 clear(scene.clear_color.r, scene.clear_color.g, scene.clear_color.b, 1.0F);
  master->setClearColor(clear);
  viewer.setSceneData(root.get());
  if (!config.stereo) {
    master->setGraphicsContext(d.gc.get());
    master->setViewport(0, 0, width, height);
    master->setDrawBuffer(GL_FRONT);
    d.clearing.push_back(master);
    master->setReadBuffer(GL_FRONT);
    master->setProjectionMatrixAsPerspective(config.fov_y_deg, static_cast<double>(width) / height,
                                             config.near, config.far);
  } else {
    // Two slave eyes side by side on one context; the master projection is the identity and
    // each eye's offset carries its full (asymmetric) projection and its IPD shift.
    master->setProjectionMatrix(osg::Matrixd::identity());
    const int eye_width = config.hmd.eye_width;
    for (int eye = 0; eye < 2; ++eye) {
      const bool left = eye == 0;
      osg::ref_ptr<osg::Camera> camera = new osg::Camera;
      camera->setGraphicsContext(d.gc.get());
      camera->setViewport(left ? 0 : eye_width, 0, eye_width, height);
      camera->setDrawBuffer(GL_FRONT);
      camera->setReadBuffer(GL_FRONT);
      camera->setClearColor(clear);
      d.clearing.push_back(camera.get());
      camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
      const double shift = (left ? 0.5 : -0.5) * config.hmd.ipd;
      viewer.addSlave(camera.get(), EyeProjection(config.hmd.fov, left, config.near, config.far),
                      osg::Matrixd::translate(shift, 0.0, 0.0), true);
    }
  }
  viewer.realize();
  if (!d.gc->isRealized()) {
    throw RenderError(
        "render: could not create an OSMesa context (OSMesaCreateContextAttribs, "
        "compatibility profile, BGRA)");
  }

  // Start-up self-check: GL_RENDERER must name a real renderer. NULL means gl* bound to a
  // dispatch stub without a context (libGL linked ahead of libOSMesa).
  d.gc->makeCurrent();
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const auto* extensions = reinterpret_cast<const char*>(glGetString(GL_EXTENSIONS));
  GLfloat max_anisotropy = 1.0F;
  if (extensions != nullptr && std::strstr(extensions, "GL_EXT_texture_filter_anisotropic") != nullptr) {
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &max_anisotropy);
  }
  d.anisotropy = std::min(static_cast<double>(config.anisotropy), static_cast<double>(max_anisotropy));
  d.gc->releaseContext();
  if (renderer == nullptr || std::strlen(renderer) == 0) {
    throw RenderError(
        "render: GL_RENDERER is NULL on the OSMesa context: the gl* functions bound to a "
        "library without a current context. Link libOSMesa ahead of libGL (render/CMakeLists.txt)"
        " and never link OpenGL::GL into the executable.");
  }
  d.renderer = renderer;
  d.version = version != nullptr ? version : "";
}

OffscreenRenderer::~OffscreenRenderer() = default;

int OffscreenRenderer::width() const { return impl_->config.image_width(); }
int OffscreenRenderer::height() const { return impl_->config.image_height(); }
const std::string& OffscreenRenderer::gl_renderer() const { return impl_->renderer; }
const std::string& OffscreenRenderer::gl_version() const { return impl_->version; }
double OffscreenRenderer::texture_anisotropy() const { return impl_->anisotropy; }

ImageView OffscreenRenderer::Render(const Eigen::Isometry3d& X_WV, const Eigen::Isometry3d& X_WC,
                                    double time) {
  Impl& d = *impl_;
  d.chair->setMatrix(ToOsg(X_WV.matrix()));
  const Eigen::Matrix4d X_WG = X_WC.matrix() * GlEyeInCamera();
  d.viewer.getCamera()->setViewMatrix(ToOsg(X_WG.inverse()));
  // With the head well inside the closed room every pixel is drawn by a room face, so clearing
  // the colour buffer (4.6 Mpx of stores in stereo, ≈ 5 % of a frame) is wasted: clear depth
  // only. The warm-up frames and any head near or beyond a wall clear both.
  const Eigen::Vector3d head = X_WC.translation();
  const bool room_covers_view =
      d.warmed_up && (head - d.room_min_W).minCoeff() > d.eye_margin &&
      (d.room_max_W - head).minCoeff() > d.eye_margin;
  for (osg::Camera* camera : d.clearing) {
    camera->setClearMask(room_covers_view ? GL_DEPTH_BUFFER_BIT
                                          : GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  if (!d.warmed_up) {
    // llvmpipe compiles shader variants on first use: draw a few frames before the real one,
    // then check that the clear actually reached the buffer (alpha of a cleared pixel = 255).
    std::memset(d.gc->mutable_pixels(), 0, static_cast<std::size_t>(width()) * height() * 4);
    for (int k = 0; k < std::max(1, d.config.warmup_frames); ++k) d.viewer.frame(time);
    if (d.gc->pixels()[3] != 255) {
      throw RenderError("render: the OSMesa buffer stayed empty after warm-up (GL_RENDERER '" +
                        d.renderer + "'); drawing does not reach the context");
    }
    d.warmed_up = true;
  }
  d.viewer.frame(time);
  return ImageView{d.gc->pixels(), width(), height()};
}

}  // namespace pwsim::render
