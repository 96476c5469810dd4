//! The stages and accesses the frame's synchronisation names, in one place.
//!
//! Every pass is ordered against whatever comes before and after it by the same, precise
//! sets (not ALL_COMMANDS and MEMORY_READ|MEMORY_WRITE, which the best-practices layer
//! flags and which serialise more than the frame needs): the shader stages that sample or
//! load the targets, the attachment stages that write them, and the copies of the read-backs
//! and the present blit. A pass therefore needs no knowledge of its neighbours, and any
//! order of passes stays correct.
//!
//! Access masks for image barriers follow the layouts (the layer checks that too):
//! SHADER_READ for SHADER_READ_ONLY_OPTIMAL (this layer version does not accept the
//! synchronization2 subset SHADER_SAMPLED_READ there), TRANSFER_READ for TRANSFER_SRC_OPTIMAL.

use ash::vk;

/// Every shader stage that reads the frame's targets and buffers.
pub const SHADER_STAGES: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
        | vk::PipelineStageFlags2::GEOMETRY_SHADER.as_raw()
        | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw()
        | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
);

/// The stages where mesh and index data are read.
pub const VERTEX_INPUT_STAGES: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT.as_raw() | vk::PipelineStageFlags2::INDEX_INPUT.as_raw(),
);

/// The (legacy) stage and access sets of a render pass's external dependencies. The subpass
/// side may name only graphics stages; the external side adds compute and transfers.
pub mod render_pass {
    use ash::vk::{AccessFlags as A, PipelineStageFlags as S};

    /// Where a pass's attachments are read and written.
    pub const ATTACHMENT_STAGES: S = S::from_raw(
        S::COLOR_ATTACHMENT_OUTPUT.as_raw() | S::EARLY_FRAGMENT_TESTS.as_raw() | S::LATE_FRAGMENT_TESTS.as_raw(),
    );
    /// Graphics shader stages (the subpass side of a dependency).
    pub const GRAPHICS_SHADERS: S =
        S::from_raw(S::VERTEX_SHADER.as_raw() | S::GEOMETRY_SHADER.as_raw() | S::FRAGMENT_SHADER.as_raw());
    /// Everything outside the pass that touches what the pass touches.
    pub const OUTSIDE: S = S::from_raw(
        GRAPHICS_SHADERS.as_raw() | S::COMPUTE_SHADER.as_raw() | ATTACHMENT_STAGES.as_raw() | S::TRANSFER.as_raw(),
    );
    /// Inside the pass: its vertex input, its shaders and its attachments.
    pub const INSIDE: S =
        S::from_raw(S::VERTEX_INPUT.as_raw() | GRAPHICS_SHADERS.as_raw() | ATTACHMENT_STAGES.as_raw());
    /// Writes that must be made available to the next user.
    pub const WRITES: A = A::from_raw(
        A::COLOR_ATTACHMENT_WRITE.as_raw()
            | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
            | A::TRANSFER_WRITE.as_raw()
            | A::SHADER_WRITE.as_raw(),
    );
    /// Sampling and drawing: what passes do with each other's targets.
    const SAMPLE_OR_DRAW: A = A::from_raw(
        A::SHADER_READ.as_raw()
            | A::COLOR_ATTACHMENT_READ.as_raw()
            | A::COLOR_ATTACHMENT_WRITE.as_raw()
            | A::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
            | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    );
    /// What a pass does with what came before it: samples it, draws into it, reads vertices.
    pub const USES: A = A::from_raw(SAMPLE_OR_DRAW.as_raw() | A::VERTEX_ATTRIBUTE_READ.as_raw());
    /// What follows a pass does with its attachments: sample, copy, or draw into again.
    pub const AFTER_USES: A =
        A::from_raw(SAMPLE_OR_DRAW.as_raw() | A::TRANSFER_READ.as_raw() | A::TRANSFER_WRITE.as_raw());
    /// The writes a pass makes to its attachments.
    pub const ATTACHMENT_WRITES: A =
        A::from_raw(A::COLOR_ATTACHMENT_WRITE.as_raw() | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw());
}
