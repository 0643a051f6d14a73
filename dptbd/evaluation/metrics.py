"""First-level detection metrics of paper 001 §4 (Table 1).

A target counts as detected in an accumulated frame (one segment's output) when a
candidate lies within Chebyshev distance ``radius`` (default 1 pixel: the 3 x 3
neighbourhood, which absorbs the rounding of a sub-pixel position and the one-pixel
"clustering" of DP energy) of the target's true pixel in the segment's last frame.
Candidates farther than that from every visible target are false points.

``Pd = detections / (accumulated frames x targets)`` as in 001's Table 1 (there with
one target: "目标检测次数 / 累加后输出总帧数").
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["DetectionCounts", "near_mask", "first_level_counts"]


@dataclasses.dataclass(frozen=True)
class DetectionCounts:
    """Summed first-level counts over trials and segments.

    Attributes
    ----------
    detections : int
        (segment, target) pairs with a candidate near the target.
    opportunities : int
        (segment, target) pairs in which the target was visible.
    false_points : int
        Candidates near no visible target, summed.
    frames : int
        Accumulated frames (segments x trials) counted.
    """

    detections: int
    opportunities: int
    false_points: int
    frames: int

    @property
    def pd(self) -> float:
        """First-level probability of detection."""
        return self.detections / self.opportunities if self.opportunities else float("nan")

    @property
    def mean_false_points(self) -> float:
        """Mean false points per accumulated frame."""
        return self.false_points / self.frames if self.frames else float("nan")

    def __add__(self, other: "DetectionCounts") -> "DetectionCounts":
        return DetectionCounts(*(getattr(self, f.name) + getattr(other, f.name)
                                 for f in dataclasses.fields(self)))


def near_mask(shape: tuple[int, int], pixels: np.ndarray, radius: int = 1) -> np.ndarray:
    """Boolean image, True within Chebyshev distance ``radius`` of any of ``pixels`` ((n, 2) rows, cols)."""
    mask = np.zeros(shape, dtype=bool)
    for row, col in np.asarray(pixels, dtype=np.int64).reshape(-1, 2):
        mask[max(row - radius, 0):row + radius + 1, max(col - radius, 0):col + radius + 1] = True
    return mask


def first_level_counts(masks: np.ndarray, truth_pixels: np.ndarray, visible: np.ndarray,
                       radius: int = 1) -> DetectionCounts:
    """Count detections and false points of candidate masks against ground truth.

    Parameters
    ----------
    masks : numpy.ndarray
        ``(S, H, W)`` boolean candidate masks, one per accumulated frame.
    truth_pixels : numpy.ndarray
        ``(S, n_targets, 2)`` integer true pixel (row, col) of each target in each
        accumulated frame's last input frame.
    visible : numpy.ndarray
        ``(S, n_targets)`` boolean: the target is in the image in that frame.
    radius : int
        Chebyshev gate in pixels.
    """
    masks = np.asarray(masks, dtype=bool)
    truth_pixels = np.asarray(truth_pixels).reshape(masks.shape[0], -1, 2)
    visible = np.asarray(visible, dtype=bool).reshape(masks.shape[0], -1)
    detections = opportunities = false_points = 0
    for mask, pix, vis in zip(masks, truth_pixels, visible):
        shown = pix[vis]
        near_any = near_mask(mask.shape, shown, radius)
        false_points += int(np.count_nonzero(mask & ~near_any))
        for target in shown:
            opportunities += 1
            detections += bool(np.any(mask & near_mask(mask.shape, target[None], radius)))
    return DetectionCounts(detections, opportunities, false_points, masks.shape[0])
