//! Command submission: one-shot work (uploads, read-backs) and the ring of frames in flight.

use super::device::Device;
use super::timing::{PassTimer, PassTimings, TimedPass};
use crate::error::{Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// Frames the CPU may record ahead of the GPU. Two: one being drawn, one being recorded.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Most timed passes one frame can record.
pub const MAX_PASSES_PER_FRAME: u32 = 16;

/// Records `record` into a fresh command buffer, submits it and waits for it. For set-up and
/// read-back only: it stalls, so it never runs on the per-frame path.
pub fn one_shot<R>(device: &Device, name: &str, record: impl FnOnce(vk::CommandBuffer) -> R) -> Result<R> {
    let raw = &device.raw;
    let pool_info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(device.queue_family)
        .flags(vk::CommandPoolCreateFlags::TRANSIENT);
    let pool = unsafe { raw.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;
    // Destroys the pool (and its command buffer) and fence on every exit path.
    struct Guard<'a> {
        device: &'a Device,
        pool: vk::CommandPool,
        fence: vk::Fence,
    }
    impl Drop for Guard<'_> {
        fn drop(&mut self) {
            unsafe {
                self.device.raw.destroy_fence(self.fence, None);
                self.device.raw.destroy_command_pool(self.pool, None);
            }
        }
    }
    let mut guard = Guard { device, pool, fence: vk::Fence::null() };
    let alloc = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1);
    let cmd = unsafe { raw.allocate_command_buffers(&alloc) }.call("vkAllocateCommandBuffers")?[0];
    device.set_name(cmd, name);
    let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
    unsafe { raw.begin_command_buffer(cmd, &begin) }.call("vkBeginCommandBuffer")?;
    let result = record(cmd);
    unsafe { raw.end_command_buffer(cmd) }.call("vkEndCommandBuffer")?;
    guard.fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) }.call("vkCreateFence")?;
    let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
    let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
    device.set_phase(&format!("submit of {name}"));
    unsafe { raw.queue_submit2(device.queue, &submit, guard.fence) }.call("vkQueueSubmit2")?;
    unsafe { raw.wait_for_fences(&[guard.fence], true, u64::MAX) }.call("vkWaitForFences")?;
    device.set_phase("idle");
    Ok(result)
}

/// One frame in flight: its command buffer, the fence that says the GPU finished it, and its
/// own timestamp pool.
pub struct FrameSlot<P> {
    /// Which of the FRAMES_IN_FLIGHT slots this is (selects per-frame uniforms and sets).
    pub index: usize,
    pub cmd: vk::CommandBuffer,
    pool: vk::CommandPool,
    fence: vk::Fence,
    pub timer: PassTimer<P>,
    submitted: bool,
}

/// The ring of frames in flight. `begin` waits only for the frame recorded
/// `FRAMES_IN_FLIGHT` frames ago, then reads that frame's timings without stalling further.
pub struct FrameRing<P> {
    slots: Vec<FrameSlot<P>>,
    current: usize,
    frames_begun: u64,
    /// Timings of the most recent frame the GPU finished.
    last_timings: PassTimings<P>,
    /// Number (0-based) of the frame `last_timings` belongs to.
    last_timed_frame: Option<u64>,
    /// Whether `last_timings` arrived since `take_fresh_timings` was last called.
    fresh: bool,
    slot_frame: [u64; FRAMES_IN_FLIGHT],
    device: Arc<Device>,
}

impl<P: TimedPass> FrameRing<P> {
    /// `statistics`: each frame's passes also count their work per shader stage (a mode that
    /// asks for it; `PassTimings::counts`).
    pub fn new(device: &Arc<Device>, statistics: bool) -> Result<Self> {
        let mut slots = Vec::with_capacity(FRAMES_IN_FLIGHT);
        for i in 0..FRAMES_IN_FLIGHT {
            let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(device.queue_family);
            let pool = unsafe { device.raw.create_command_pool(&pool_info, None) }.call("vkCreateCommandPool")?;
            let alloc = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1);
            let cmd = match unsafe { device.raw.allocate_command_buffers(&alloc) } {
                Ok(c) => c[0],
                Err(e) => {
                    unsafe { device.raw.destroy_command_pool(pool, None) };
                    return Err(e).call("vkAllocateCommandBuffers");
                }
            };
            let fence_info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let fence = match unsafe { device.raw.create_fence(&fence_info, None) } {
                Ok(f) => f,
                Err(e) => {
                    unsafe { device.raw.destroy_command_pool(pool, None) };
                    return Err(e).call("vkCreateFence");
                }
            };
            let timer = match PassTimer::new(device, &format!("frame {i} timestamps"), MAX_PASSES_PER_FRAME, statistics)
            {
                Ok(t) => t,
                Err(e) => {
                    unsafe {
                        device.raw.destroy_fence(fence, None);
                        device.raw.destroy_command_pool(pool, None);
                    }
                    return Err(e);
                }
            };
            device.set_name(cmd, &format!("frame {i} commands"));
            device.set_name(fence, &format!("frame {i} fence"));
            slots.push(FrameSlot { index: i, cmd, pool, fence, timer, submitted: false });
        }
        Ok(Self {
            slots,
            current: 0,
            frames_begun: 0,
            last_timings: PassTimings::default(),
            last_timed_frame: None,
            fresh: false,
            slot_frame: [0; FRAMES_IN_FLIGHT],
            device: device.clone(),
        })
    }

    /// Waits for the slot's previous frame, harvests its timings, and starts recording.
    pub fn begin(&mut self) -> Result<&mut FrameSlot<P>> {
        self.retire(self.current, &mut |_, _| {})?;
        let dev = &self.device.raw;
        let slot = &mut self.slots[self.current];
        unsafe { dev.reset_command_pool(slot.pool, vk::CommandPoolResetFlags::empty()) }.call("vkResetCommandPool")?;
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        unsafe { dev.begin_command_buffer(slot.cmd, &begin) }.call("vkBeginCommandBuffer")?;
        slot.timer.begin_frame(slot.cmd);
        self.slot_frame[self.current] = self.frames_begun;
        self.frames_begun += 1;
        Ok(slot)
    }

    /// Ends the current frame's recording without submitting it (e.g. the swapchain went
    /// out of date after `begin`). Its fence stays signalled, so the slot is free.
    pub fn abandon(&mut self) -> Result<()> {
        let slot = &mut self.slots[self.current];
        unsafe { self.device.raw.end_command_buffer(slot.cmd) }.call("vkEndCommandBuffer")
    }

    /// Ends and submits the current frame. `waits`/`signals` connect it to a swapchain.
    pub fn submit(
        &mut self,
        waits: &[vk::SemaphoreSubmitInfo<'_>],
        signals: &[vk::SemaphoreSubmitInfo<'_>],
    ) -> Result<()> {
        let dev = &self.device.raw;
        let slot = &mut self.slots[self.current];
        unsafe { dev.end_command_buffer(slot.cmd) }.call("vkEndCommandBuffer")?;
        // Reset only now: a frame abandoned before submission must not leave an unsignalled
        // fence that the next `begin` would wait on forever.
        unsafe { dev.reset_fences(&[slot.fence]) }.call("vkResetFences")?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(slot.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(signals)];
        self.device.set_phase("frame submission");
        unsafe { dev.queue_submit2(self.device.queue, &submit, slot.fence) }.call("vkQueueSubmit2")?;
        slot.submitted = true;
        self.current = (self.current + 1) % FRAMES_IN_FLIGHT;
        Ok(())
    }

    /// Waits for every submitted frame and harvests their timings oldest first, handing each
    /// to `on_timings` (frame number, timings); afterwards `last_timings` is the newest frame's.
    pub fn finish(&mut self, mut on_timings: impl FnMut(u64, &PassTimings<P>)) -> Result<()> {
        for k in 0..FRAMES_IN_FLIGHT {
            self.retire((self.current + k) % FRAMES_IN_FLIGHT, &mut on_timings)?;
        }
        self.fresh = false;
        Ok(())
    }

    fn retire(&mut self, index: usize, on_timings: &mut dyn FnMut(u64, &PassTimings<P>)) -> Result<()> {
        let slot = &mut self.slots[index];
        unsafe { self.device.raw.wait_for_fences(&[slot.fence], true, u64::MAX) }.call("vkWaitForFences")?;
        if slot.submitted {
            slot.submitted = false;
            if slot.timer.read(&mut self.last_timings)? {
                self.last_timed_frame = Some(self.slot_frame[index]);
                self.fresh = true;
                on_timings(self.slot_frame[index], &self.last_timings);
            }
        }
        Ok(())
    }

    /// The timings a `begin` harvested since the last call, once each.
    pub fn take_fresh_timings(&mut self) -> Option<(u64, &PassTimings<P>)> {
        if std::mem::take(&mut self.fresh) {
            self.last_timings()
        } else {
            None
        }
    }

    /// Timings of the newest frame the GPU has finished, and that frame's number.
    pub fn last_timings(&self) -> Option<(u64, &PassTimings<P>)> {
        self.last_timed_frame.map(|f| (f, &self.last_timings))
    }
}

impl<P> Drop for FrameRing<P> {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.raw.device_wait_idle();
            for slot in &self.slots {
                self.device.raw.destroy_fence(slot.fence, None);
                self.device.raw.destroy_command_pool(slot.pool, None);
            }
        }
    }
}
