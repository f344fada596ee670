#include "precompute/mesh_import.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <type_traits>

#include "core/error.h"
#include "core/resources.h"
#include "core/text.h"

namespace acpca {

namespace {

// --- What the child sends: a flat byte stream --------------------------------

class Writer {
 public:
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void text(const std::string& s) {
    value<std::uint64_t>(s.size());
    bytes_ += s;
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    value<std::uint64_t>(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  template <typename T>
  T value() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  std::string text() {
    std::string s(count(1), '\0');
    take(s.data(), s.size());
    return s;
  }
  template <typename T>
  std::vector<T> array() {
    std::vector<T> v(count(sizeof(T)));
    take(v.data(), v.size() * sizeof(T));
    return v;
  }
  bool atEnd() const { return at_ == bytes_.size(); }

 private:
  size_t count(size_t elementBytes) {
    const auto n = value<std::uint64_t>();
    if (n > (bytes_.size() - at_) / elementBytes) broken();
    return static_cast<size_t>(n);
  }
  void take(void* out, size_t n) {
    if (n == 0) return;  // an empty array's data() may be null
    if (n > bytes_.size() - at_) broken();
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  [[noreturn]] void broken() const {
    throw UserError(concat(path_, ": cannot read the mesh: the importer's answer was cut short"));
  }
  const std::string& bytes_;
  std::string path_;
  size_t at_ = 0;
};

void sendModel(Writer& w, const ImportedModel& m) {
  w.value<std::uint64_t>(m.materials.size());
  for (const auto& mat : m.materials) {
    w.text(mat.name);
    for (float c : mat.color) w.value(c);
    w.value(mat.hasColor);
    w.text(mat.textureReference);
    w.value(mat.uvSet);
    w.value(mat.textureTransformed);
    w.value(mat.embedded);
    w.text(mat.formatHint);
    w.value(mat.embeddedWidth);
    w.value(mat.embeddedHeight);
    w.array(mat.embeddedBytes);
  }
  w.value<std::uint64_t>(m.parts.size());
  for (const auto& p : m.parts) {
    w.text(p.name);
    w.value(p.material);
    w.array(p.positions);
    w.array(p.normals);
    w.array(p.uvs);
    w.array(p.tangents);
    w.array(p.corners);
  }
}

ImportedModel receiveModel(Reader& r) {
  ImportedModel m;
  // Counts come from the stream: grow as the bytes go, never by a count.
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) {
    ImportedMaterial& mat = m.materials.emplace_back();
    mat.name = r.text();
    for (float& c : mat.color) c = r.value<float>();
    mat.hasColor = r.value<bool>();
    mat.textureReference = r.text();
    mat.uvSet = r.value<unsigned>();
    mat.textureTransformed = r.value<bool>();
    mat.embedded = r.value<bool>();
    mat.formatHint = r.text();
    mat.embeddedWidth = r.value<unsigned>();
    mat.embeddedHeight = r.value<unsigned>();
    mat.embeddedBytes = r.array<std::uint8_t>();
  }
  for (auto n = r.value<std::uint64_t>(); n > 0; --n) {
    ImportedPart& p = m.parts.emplace_back();
    p.name = r.text();
    p.material = r.value<unsigned>();
    p.positions = r.array<float>();
    p.normals = r.array<float>();
    p.uvs = r.array<float>();
    p.tangents = r.array<float>();
    p.corners = r.array<std::uint32_t>();
  }
  return m;
}

// --- The child: assimp's scene to plain arrays -------------------------------

constexpr int kMaxNodeDepth = 1000;

ImportedMaterial readMaterial(const aiScene* ai, unsigned index) {
  ImportedMaterial out;
  const aiMaterial* m = ai->mMaterials ? ai->mMaterials[index] : nullptr;
  if (!m) return out;
  out.name = m->GetName().C_Str();
  // glTF's baseColorFactor, else the diffuse colour (OBJ Kd, Collada diffuse).
  aiColor4D color;
  if (m->Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
      m->Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) {
    out.color[0] = color.r, out.color[1] = color.g, out.color[2] = color.b;
    out.hasColor = true;
  }
  for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
    if (m->GetTextureCount(type) == 0) continue;
    aiString file;
    unsigned uvSet = 0;
    if (m->GetTexture(type, 0, &file, nullptr, &uvSet) != AI_SUCCESS) continue;
    out.textureReference = file.C_Str();
    out.uvSet = uvSet;
    aiUVTransform transform;
    out.textureTransformed = m->Get(AI_MATKEY_UVTRANSFORM(type, 0), transform) == AI_SUCCESS &&
                             (transform.mTranslation != aiVector2D(0, 0) ||
                              transform.mScaling != aiVector2D(1, 1) || transform.mRotation != 0);
    if (const aiTexture* embedded = ai->GetEmbeddedTexture(file.C_Str())) {
      out.embedded = true;
      out.formatHint = std::string(embedded->achFormatHint, strnlen(embedded->achFormatHint, 9));
      out.embeddedWidth = embedded->mWidth;
      out.embeddedHeight = embedded->mHeight;
      const size_t bytes = embedded->mHeight == 0
                               ? size_t(embedded->mWidth)
                               : size_t(embedded->mWidth) * embedded->mHeight * sizeof(aiTexel);
      if (embedded->pcData && bytes > 0) {
        const auto* data = reinterpret_cast<const std::uint8_t*>(embedded->pcData);
        out.embeddedBytes.assign(data, data + bytes);
      }
    }
    break;
  }
  return out;
}

void collectParts(const aiScene* ai, const aiNode* node, const aiMatrix4x4& parent, int depth,
                  ImportedModel& out) {
  if (!node) return;
  if (depth > kMaxNodeDepth)
    throw UserError(concat("its node tree is deeper than ", kMaxNodeDepth, " levels"));
  const aiMatrix4x4 transform = parent * node->mTransformation;
  aiMatrix3x3 normalTransform(transform);
  normalTransform.Inverse().Transpose();
  for (unsigned i = 0; i < node->mNumMeshes && node->mMeshes; ++i) {
    const unsigned index = node->mMeshes[i];
    if (index >= ai->mNumMeshes || !ai->mMeshes || !ai->mMeshes[index])
      throw UserError(concat("a node names mesh ", index, " of ", ai->mNumMeshes));
    const aiMesh* mesh = ai->mMeshes[index];
    ImportedPart part;
    part.name = mesh->mName.C_Str();
    part.material = mesh->mMaterialIndex;
    const unsigned vertices = mesh->mVertices ? mesh->mNumVertices : 0;
    part.positions.reserve(3 * size_t(vertices));
    for (unsigned v = 0; v < vertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      part.positions.insert(part.positions.end(), {p.x, p.y, p.z});
    }
    if (mesh->mNormals && vertices > 0) {
      part.normals.reserve(3 * size_t(vertices));
      for (unsigned v = 0; v < vertices; ++v) {
        const aiVector3D n = normalTransform * mesh->mNormals[v];
        part.normals.insert(part.normals.end(), {n.x, n.y, n.z});
      }
    }
    if (mesh->mTangents && vertices > 0) {
      const aiMatrix3x3 linear(transform);  // tangents lie in the surface
      part.tangents.reserve(3 * size_t(vertices));
      for (unsigned v = 0; v < vertices; ++v) {
        const aiVector3D t = linear * mesh->mTangents[v];
        part.tangents.insert(part.tangents.end(), {t.x, t.y, t.z});
      }
    }
    const unsigned uvSet =
        part.material < out.materials.size() ? out.materials[part.material].uvSet : 0;
    if (uvSet < AI_MAX_NUMBER_OF_TEXTURECOORDS && mesh->mTextureCoords[uvSet] && vertices > 0)
      for (unsigned v = 0; v < vertices; ++v)
        part.uvs.insert(part.uvs.end(),
                        {mesh->mTextureCoords[uvSet][v].x, mesh->mTextureCoords[uvSet][v].y});
    for (unsigned f = 0; f < mesh->mNumFaces && mesh->mFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;  // points and lines
      part.corners.insert(part.corners.end(),
                          {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
    }
    out.parts.push_back(std::move(part));
  }
  for (unsigned c = 0; c < node->mNumChildren && node->mChildren; ++c)
    collectParts(ai, node->mChildren[c], transform, depth + 1, out);
}

ImportedModel importModel(const std::string& path) {
  Assimp::Importer importer;
  // No vertex joining or normal generation: the file's normals or our own.
  // Tangents: the file's (glTF TANGENT), else from the first texture
  // coordinates where a part has them and normals.
  const aiScene* ai = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_CalcTangentSpace);
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string reason = importer.GetErrorString();
    // assimp reports its exceptions' what(); a malformed count asks for GBs.
    if (reason.find("bad_alloc") != std::string::npos)
      throw UserError(
          "cannot read the mesh: the importer (assimp) ran out of memory on it (a "
          "malformed count in the file?)");
    throw UserError(
        concat("cannot read the mesh: ", reason.empty() ? "assimp gave no reason" : reason));
  }
  ImportedModel model;
  for (unsigned m = 0; m < ai->mNumMaterials; ++m) model.materials.push_back(readMaterial(ai, m));
  collectParts(ai, ai->mRootNode, aiMatrix4x4(), 0, model);
  return model;
}

/// The child's whole life: read, send, exit without running the parent's
/// destructors or exit handlers.
[[noreturn]] void runChild(const std::string& path, int fd, rlim_t addressSpace, pid_t parent) {
  // A crash here ends this process alone, by the signal's default action.
  for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM}) ::signal(s, SIG_DFL);
  // An importer stuck in a loop must not outlive the process waiting for it
  // (killed, or interrupted by a signal sent to it alone).
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(3);  // it died before the line above
  if (addressSpace > 0) {
    const rlimit limit{addressSpace, addressSpace};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  Writer w;
  try {
    ImportedModel model = importModel(path);
    w.value<char>('+');
    sendModel(w, model);
  } catch (const std::exception& e) {
    w.bytes().clear();
    w.value<char>('-');
    w.text(e.what());
  }
  const std::string& bytes = w.bytes();
  for (size_t at = 0; at < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
    if (n <= 0) ::_exit(2);
    at += static_cast<size_t>(n);
  }
  ::_exit(0);
}

/// The memory the child may take beyond what it shares with this process at
/// the fork: malformed headers make assimp ask for many GB (invalid/
/// OutOfMemory.off asks for 16 GB). A budget for the file, at most what is
/// available.
struct ChildMemory {
  long long budget = 0;
  long long mapped = 0;    ///< this process's address space at the fork
  long long resident = 0;  ///< and its resident pages, which the child starts with
};

long long pageCount(const std::string& statm, int field) {
  std::ifstream in(statm);
  long long value = 0;
  for (int i = 0; i <= field && in >> value; ++i) {
  }
  return value * ::sysconf(_SC_PAGESIZE);
}

ChildMemory childMemory(const std::string& path) {
  ChildMemory m;
  m.mapped = pageCount("/proc/self/statm", 0);
  m.resident = pageCount("/proc/self/statm", 1);
  const long long available = availableMemoryBytes();
  std::error_code ec;
  const auto fileBytes = static_cast<long long>(std::filesystem::file_size(path, ec));
  m.budget = std::max(4LL << 30, 256 * (ec ? 0 : fileBytes));
  m.budget = std::min(m.budget, std::max(available / 4 * 3, 1LL << 30));
  return m;
}

/// The child's address-space limit; 0 (none) under AddressSanitizer, which
/// reserves terabytes for its shadow: its resident pages are watched instead.
rlim_t addressSpaceLimit(const ChildMemory& m) {
#if defined(__SANITIZE_ADDRESS__)
  return 0;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return 0;
#endif
#endif
  return static_cast<rlim_t>(m.mapped + m.budget);
}

std::string signalName(int s) {
  const char* name = sigabbrev_np(s);
  return name ? concat("SIG", name) : concat("signal ", s);
}

}  // namespace

double defaultImportSeconds(const std::string& path) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  return 60.0 + (ec ? 0.0 : static_cast<double>(bytes) / (1 << 20));
}

ImportedModel importModelIsolated(const std::string& path, double seconds) {
  if (seconds < 0) seconds = defaultImportSeconds(path);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw UserError(concat(path, ": cannot read the mesh: no pipe for the importer"));
  const ChildMemory memory = childMemory(path);
  const rlim_t addressSpace = addressSpaceLimit(memory);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw UserError(concat(path, ": cannot read the mesh: cannot start the importer"));
  }
  if (pid == 0) {
    ::close(fds[0]);
    runChild(path, fds[1], addressSpace, parent);
  }
  ::close(fds[1]);
  // Read while it writes (a pipe holds only 64 KiB), up to the time limit.
  std::string bytes;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  bool timedOut = false, outOfMemory = false;
  const std::string childStatm = concat("/proc/", pid, "/statm");
  char buffer[1 << 16];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      timedOut = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 50)));
    if (pageCount(childStatm, 1) > memory.resident + memory.budget) {
      outOfMemory = true;
      break;
    }
    if (ready <= 0) continue;
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its end: done or dead
    bytes.append(buffer, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  if (timedOut || outOfMemory) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string prefix = concat(path, ": cannot read the mesh: ");
  if (timedOut)
    throw UserError(concat(prefix, "the importer (assimp) did not finish within ", seconds, " s"));
  if (outOfMemory)
    throw UserError(concat(prefix, "the importer (assimp) took more than ",
                           formatBytes(memory.budget), " on it (a malformed count in the file?)"));
  if (WIFSIGNALED(status))
    throw UserError(concat(prefix, "the importer (assimp) crashed on it (",
                           signalName(WTERMSIG(status)), "); the file is probably malformed"));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty())
    throw UserError(concat(prefix, "the importer (assimp) stopped with status ",
                           WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  Reader r(bytes, path);
  if (r.value<char>() == '-') {
    const std::string message = r.text();
    throw UserError(concat(path, ": ", message));
  }
  ImportedModel model = receiveModel(r);
  if (!r.atEnd()) throw UserError(concat(prefix, "the importer's answer has trailing bytes"));
  return model;
}

}  // namespace acpca
