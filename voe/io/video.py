"""Writing one clip's frames to disk: an mp4 file or a folder of PNGs.

Why a module of its own: the export decides *what* goes where (names, tables, layouts); this
decides only *how* frames become bytes, with settings chosen so that the same frames give the
same bytes (no timestamps, no encoder version strings, one encoder thread).

mp4: H.264 (libx264) through the ffmpeg binary that the ``imageio-ffmpeg`` package ships (optional
extra ``video``), constant quantiser 0 in 4:4:4 YUV, i.e. lossless in YUV: a decoded pixel is within
2 levels of the rendered one (RGB to YUV rounding), and colours are not subsampled.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from voe.errors import VoeError

#: ffmpeg output options: lossless-in-YUV H.264, reproducible bytes.
MP4_PARAMS = ("-qp", "0", "-preset", "veryfast", "-threads", "1", "-fflags", "+bitexact",
              "-flags:v", "+bitexact", "-map_metadata", "-1")
MP4_PIX_FMT = "yuv444p"


def _imageio_ffmpeg():
    try:
        import imageio_ffmpeg
    except ImportError as exc:  # optional extra
        raise VoeError("--format mp4 needs the ffmpeg that imageio-ffmpeg ships: "
                       "pip install 'voe[video]' (or use --format png)") from exc
    return imageio_ffmpeg


def ffmpeg_version() -> str:
    """Version of the bundled ffmpeg (recorded in export manifests)."""
    return str(_imageio_ffmpeg().get_ffmpeg_version())


def _rgb(frames: np.ndarray) -> np.ndarray:
    """``(T, H, W)`` or ``(T, H, W, 3)`` uint8 -> contiguous ``(T, H, W, 3)``."""
    if frames.ndim == 3:
        frames = np.repeat(frames[..., None], 3, axis=-1)
    return np.ascontiguousarray(frames, dtype=np.uint8)


def write_mp4(path: Path, frames: np.ndarray, fps: float) -> None:
    """Encode ``frames`` (T, H, W[, 3]) uint8 to ``path`` (its folder must exist)."""
    iio = _imageio_ffmpeg()
    rgb = _rgb(frames)
    T, H, W, _ = rgb.shape
    writer = iio.write_frames(str(path), (W, H), pix_fmt_in="rgb24", pix_fmt_out=MP4_PIX_FMT,
                              fps=fps, quality=None, codec="libx264", macro_block_size=1,
                              ffmpeg_log_level="error", output_params=list(MP4_PARAMS))
    writer.send(None)  # start ffmpeg
    for frame in rgb:
        writer.send(frame)
    writer.close()


def read_mp4(path: Path) -> np.ndarray:
    """Decode an mp4 to ``(T, H, W, 3)`` uint8 (tests and users checking an export)."""
    reader = _imageio_ffmpeg().read_frames(str(path), pix_fmt="rgb24")
    meta = next(reader)
    W, H = meta["size"]
    frames = [np.frombuffer(b, dtype=np.uint8).reshape(H, W, 3) for b in reader]
    return np.stack(frames)


def write_pngs(folder: Path, frames: np.ndarray, name: str = "{:03d}.png", first: int = 0) -> list[Path]:
    """Write one PNG per frame into ``folder`` (created); returns the paths in frame order.

    ``name`` formats the frame number, counted from ``first`` (IntPhys counts from 1).
    """
    from PIL import Image

    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for i, frame in enumerate(np.asarray(frames, dtype=np.uint8)):
        p = folder / name.format(first + i)
        Image.fromarray(frame).save(p, format="PNG", compress_level=1)
        out.append(p)
    return out
