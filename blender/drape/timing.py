"""Blender's clock as Drape's: one formula for the handler, the bake and the tests."""


def drape_seconds(frame, subframe, offset_frames, fps, fps_base):
    """Seconds into the Drape scene at Blender's (frame + subframe).

    t = (frame + subframe − offset) × fps_base / fps, with Blender's fps and
    fps_base: the cloth keeps its speed in seconds whatever the .ron's fps is.
    """
    return (frame + subframe - offset_frames) * fps_base / fps


def blender_frame(seconds, offset_frames, fps, fps_base):
    """The Blender (frame, subframe) at which the Drape scene is `seconds` in: drape_seconds' inverse."""
    exact = seconds * fps / fps_base + offset_frames
    frame = int(exact // 1)
    return frame, exact - frame


def blender_fps(render):
    return render.fps / render.fps_base


def fps_mismatch(render, drape_fps):
    """A warning when Blender's frame rate is not the scene file's, else None."""
    ours = blender_fps(render)
    if abs(ours - drape_fps) <= 1e-6 * drape_fps:
        return None
    return (
        f"Blender plays {ours:g} fps, the Drape scene was timed at {drape_fps:g} fps: "
        "times match in seconds, so Drape's frame numbers do not match Blender's"
    )
