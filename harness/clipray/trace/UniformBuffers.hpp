#pragma once
// The matrices an app keeps in uniform buffers, followed through a trace's calls for
// `clipray check --trace`: buffer contents (glBufferData, glBufferSubData, glBufferStorage, their
// glNamed* forms, glCopyBufferSubData, and glMapBuffer*/glMapNamedBuffer* writes, which apitrace
// records as a fake `memcpy(dest, src = blob(...), n)` call before the unmap), the indexed
// GL_UNIFORM_BUFFER bindings (glBindBufferBase / glBindBufferRange, glBindBuffersBase/Range),
// each program's uniform blocks (the GLSL of its attached shaders' glShaderSource) and their
// bindings (layout(binding) or glUniformBlockBinding, with the block index from
// glGetUniformBlockIndex's result).
//
// The bytes of buffers bound to GL_UNIFORM_BUFFER are kept (from that binding on, or from their
// glBufferData when bound first), and of small buffers written with glNamedBuffer* before any
// binding; vertex and index data are not held.
//
// Buffer bytes come from the blob files `apitrace dump --blobs` writes (blob_call<N>.bin in the
// dump's working directory); without that directory every buffer's contents are unknown.
//
// Only std140 blocks are read: shared and packed blocks have implementation-defined offsets
// (std430 is for storage blocks). Where a block cannot be read — its layout, a member type whose
// offset is not followed, nothing bound, a range shorter than the block, bytes never written
// where the trace shows them — the reason is noted, never guessed around.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/trace/DumpLine.hpp"
#include "clipray/trace/Std140Layout.hpp"

namespace clipray::trace {

// A buffer's contents are followed up to this size (a camera block is a few hundred bytes; a
// ring buffer of per-draw blocks a few MiB) ...
inline constexpr std::uint64_t kMaxFollowedBufferBytes = 16u << 20;
// ... and up to this much in all, which bounds the memory a trace's buffers take.
inline constexpr std::uint64_t kMaxFollowedBufferTotal = 256u << 20;
// A buffer written with glNamedBuffer* before it is ever bound is followed up to this size:
// GL_MAX_UNIFORM_BLOCK_SIZE on common drivers, so a buffer made for one block fits, and
// vertex data of a DSA app mostly does not.
inline constexpr std::uint64_t kMaxUniformBlockBytes = 64u << 10;
// Of a mat4 array (a bone palette), at most this many elements are read at each draw.
inline constexpr std::uint32_t kMaxMatricesPerArray = 256;
// glBindBuffersBase/Range set at most this many bindings (GL_MAX_UNIFORM_BUFFER_BINDINGS is
// 84 or so on current drivers; a damaged count must not loop for long).
inline constexpr std::uint32_t kMaxMultiBindCount = 1024;
// At most this many distinct reasons for a block not read are kept.
inline constexpr std::size_t kMaxUnreadNotes = 20;

// A mat4 member of a bound uniform block, read at a draw.
struct UniformBlockMatrix {
  std::string source;      // "ubo Camera.clipFromWorld (program 1)"
  glm::dmat4 matrix{1.0};  // column-major as the shader applies it (row_major undone)
};

class UniformBuffers {
 public:
  // The folder `apitrace dump --blobs` writes its blob files into.
  void setBlobDirectory(std::filesystem::path directory) { blobDirectory_ = std::move(directory); }

  // Whether apply needs this function.
  static bool needs(std::string_view function);

  // Feeds one call (needs(call.name)). Throws std::invalid_argument where an argument it needs
  // cannot be read.
  void apply(const DumpCall& call);

  // The mat4 members of the program's std140 uniform blocks, read from the buffer ranges bound
  // to their bindings now; members that cannot be read are noted (unreadNotes) and left out.
  std::vector<UniformBlockMatrix> matrices(std::uint32_t program, std::uint64_t drawCall);

  // Whether the program's shaders write gl_ClipDistance (their text, comments and preprocessor
  // lines left out, names it): kept here beside the shader text the blocks are read from.
  bool writesClipDistance(std::uint32_t program) const {
    return programsWritingClipDistance_.contains(program);
  }
  // Whether one of the program's shaders assigns gl_FragDepth where its preprocessor keeps the
  // line (FragDepthWrite.hpp): its depth is what the shader computes, not the projective one.
  bool writesFragDepth(std::uint32_t program) const {
    return programsWritingFragDepth_.contains(program);
  }

  // Why the program's vertices go through the fixed-function GL_PROJECTION: "its vertex shader
  // calls ftransform()", "its vertex shader reads gl_ProjectionMatrix", "it has no vertex
  // shader" (every attached shader's glCreateShader type known, none a vertex shader); "" when
  // its vertex shader reads none of them, or what it links is not in the trace.
  std::string fixedFunctionTransform(std::uint32_t program) const {
    const auto found = programsFixedFunction_.find(program);
    return found != programsFixedFunction_.end() ? found->second : std::string();
  }

  // Why blocks or their matrices were not read: one line per distinct reason, the first call
  // where it applied, at most kMaxUnreadNotes.
  const std::vector<std::string>& unreadNotes() const { return notes_; }

 private:
  struct Buffer {
    std::uint64_t size = 0;
    bool uniform = false;   // bound to GL_UNIFORM_BUFFER at some point
    bool followed = false;  // contents kept (see kMaxFollowedBuffer*)
    std::vector<std::uint8_t> bytes;
    std::vector<bool> written;  // per byte: whether the trace shows what it holds
    std::string unwrittenWhy;   // why the last bytes not shown are not (for the notes)
  };
  struct Range {
    std::uint32_t buffer = 0;
    std::uint64_t offset = 0;
    std::optional<std::uint64_t> size;  // none: to the end of the buffer (glBindBufferBase)
  };
  struct Mapping {
    std::uint32_t buffer = 0;
    std::uint64_t offset = 0, length = 0;
  };
  struct LinkedBlock {
    UniformBlockDeclaration declaration;
    std::uint32_t binding = 0;
  };

  // A new data store (glBufferData, glBufferStorage); asUniform: through GL_UNIFORM_BUFFER.
  void allocate(std::uint32_t buffer, std::uint64_t size, bool asUniform, const DumpCall& call,
                const DumpValue& data);
  // Keeps the buffer's bytes from now on (within kMaxFollowedBuffer*), none of them known yet.
  void follow(std::uint32_t buffer, const std::string& unwrittenWhy);
  // The buffer is bound as a uniform buffer: its bytes are followed from here on.
  void followFromNowOn(std::uint32_t buffer, const DumpCall& call);
  void write(std::uint32_t buffer, std::uint64_t offset, std::uint64_t size, const DumpCall& call,
             const DumpValue& data);
  // The bytes a data argument holds (a blob file of the dump); nullopt, with the reason in why,
  // when they are not available.
  std::optional<std::vector<std::uint8_t>> blobBytes(const DumpCall& call, const DumpValue& data,
                                                     std::uint64_t size, std::string& why) const;
  void link(std::uint32_t program);

  // apply's steps: one per GL function it follows, with that function's Base/Range or glNamed*
  // forms.
  // glBindBuffer: the buffer bound to a target, for the calls that name the target.
  void bindBuffer(const DumpCall& call);
  // glBindBufferBase, glBindBufferRange: one indexed uniform buffer binding.
  void bindBufferBaseOrRange(const DumpCall& call);
  // glBindBuffersBase, glBindBuffersRange: consecutive indexed uniform buffer bindings.
  void bindBuffersBaseOrRange(const DumpCall& call);
  void deleteBuffers(const DumpCall& call);
  // glCopyBufferSubData, glCopyNamedBufferSubData.
  void copyBufferSubData(const DumpCall& call);
  // glMapBuffer*, glMapNamedBuffer*: where the mapping is, for the memcpy calls that write it.
  void mapBuffer(const DumpCall& call);
  // glUnmapBuffer, glUnmapNamedBuffer.
  void unmapBuffer(const DumpCall& call);
  // memcpy: apitrace's record of the bytes an app wrote into a mapping (its fake memcpy call).
  void writeMapped(const DumpCall& call);
  // glCreateShaderProgramv: a program linked from one shader's source.
  void createShaderProgram(const DumpCall& call);
  // glGetUniformBlockIndex, glGetActiveUniformBlockName: the block name behind an index, for
  // glUniformBlockBinding.
  void nameBlockIndex(const DumpCall& call);
  // glUniformBlockBinding.
  void bindUniformBlock(const DumpCall& call);

  // The buffer bound to a call's target argument (argument name given); 0 for none.
  std::uint32_t bufferAt(const DumpCall& call, std::string_view targetArgument) const;
  void note(const std::string& key, const std::string& message);

  std::optional<std::filesystem::path> blobDirectory_;
  std::map<std::uint32_t, Buffer> buffers_;
  std::uint64_t followedBytes_ = 0;
  std::map<std::string, std::uint32_t> targets_;    // target as written -> buffer (glBindBuffer)
  std::map<std::uint32_t, Range> uniformBindings_;  // GL_UNIFORM_BUFFER binding index -> range
  std::map<std::uint64_t, Mapping> mappings_;       // mapped address -> buffer range

  std::map<std::uint32_t, std::string> shaderSources_;
  std::map<std::uint32_t, std::vector<std::uint32_t>> attachedShaders_;
  std::map<std::uint32_t, std::vector<LinkedBlock>> programBlocks_;
  std::set<std::uint32_t> programsWritingClipDistance_;
  std::set<std::uint32_t> programsWritingFragDepth_;
  std::map<std::uint32_t, std::uint32_t> shaderTypes_;  // glCreateShader's result -> its type
  std::map<std::uint32_t, std::string> programsFixedFunction_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::string> blockIndexNames_;

  std::map<std::string, std::size_t> notedKeys_;
  std::vector<std::string> notes_;
};

}  // namespace clipray::trace
