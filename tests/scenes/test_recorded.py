"""Loading recorded sequences: .npy, .npz, folders of 8/16-bit PNG/TIFF; bad input refused."""

import numpy as np
import pytest
from PIL import Image

from dptbd.scenes.recorded import SequenceError, load_sequence
from helpers.refusals import whole


def frames(dtype=np.uint16, t=4, h=6, w=5, top=4095):
    rng = np.random.default_rng(0)
    return rng.integers(0, top + 1, (t, h, w)).astype(dtype)


def write_images(folder, arrs, fmt="png", names=None):
    folder.mkdir(exist_ok=True)
    for i, a in enumerate(arrs):
        name = names[i] if names else f"frame{i}.{fmt}"
        Image.fromarray(a).save(folder / name)


def test_npy_uint16_and_uint8(tmp_path):
    a = frames()
    np.save(tmp_path / "a.npy", a)
    seq = load_sequence(tmp_path / "a.npy")
    assert seq.input_bits == 16 and seq.frames.dtype == np.uint16
    np.testing.assert_array_equal(seq.frames, a)
    b = frames(np.uint8, top=255)
    np.save(tmp_path / "b.npy", b)
    seq = load_sequence(tmp_path / "b.npy")
    assert seq.input_bits == 8 and seq.frames.dtype == np.uint8


def test_npy_wide_integers_in_range_are_16_bit(tmp_path):
    np.save(tmp_path / "a.npy", frames(np.int64))
    seq = load_sequence(tmp_path / "a.npy")
    assert seq.input_bits == 16 and seq.frames.dtype == np.uint16


@pytest.mark.parametrize("arr, message", [
    (np.zeros((3, 6, 5), np.float32), "frames must be integers, got dtype float32 (quantise float "
     "frames to integers first, e.g. with dptbd.scenes.synthetic.quantise)"),
    (np.zeros((6, 5), np.uint16),
     "one frame of shape (6, 5); a sequence needs shape (frames, height, width)"),
    (np.zeros((0, 6, 5), np.uint16), "the sequence is empty (0 frames)"),
    (np.zeros((2, 2, 5), np.uint16), "frames are 2 x 5 (H x W); the DP needs at least 3 x 3"),
    (np.full((2, 6, 5), 70000, np.int32),
     "pixel values must be in [0, 65535] (8 or 16 bits), found [70000, 70000]"),
    (np.full((2, 6, 5), -1, np.int16), "pixel values must be in [0, 65535] (8 or 16 bits), found [-1, -1]"),
    (np.zeros((2, 3, 6, 5), np.uint16),
     "a sequence must have shape (frames, height, width), got shape (2, 3, 6, 5)"),
    (np.zeros((2, 6, 5), bool), "frames must be integers, got dtype bool"),
])
def test_npy_bad_arrays_are_refused(tmp_path, arr, message):
    np.save(tmp_path / "bad.npy", arr)
    with pytest.raises(SequenceError, match=whole(f"{tmp_path / 'bad.npy'}: {message}")):
        load_sequence(tmp_path / "bad.npy")


def test_npz_single_array_named_key_and_frames(tmp_path):
    a = frames()
    np.savez(tmp_path / "one.npz", whatever=a)
    np.testing.assert_array_equal(load_sequence(tmp_path / "one.npz").frames, a)
    np.savez(tmp_path / "two.npz", frames=a, other=a[:1])
    assert load_sequence(tmp_path / "two.npz").source.endswith("[frames]")
    assert load_sequence(tmp_path / "two.npz", key="other").frames.shape[0] == 1
    np.savez(tmp_path / "amb.npz", x=a, y=a)
    with pytest.raises(SequenceError, match=whole(
            f"{tmp_path / 'amb.npz'} holds 2 arrays ['x', 'y']; name the one to use (--npz-key, "
            "or [input] key)")):
        load_sequence(tmp_path / "amb.npz")
    with pytest.raises(SequenceError, match=whole(
            f"{tmp_path / 'amb.npz'} has no array 'z'; it holds ['x', 'y']")):
        load_sequence(tmp_path / "amb.npz", key="z")


def test_png_folder_8_bit_in_natural_order(tmp_path):
    a = frames(np.uint8, t=12, top=255)
    names = [f"f{i}.png" for i in range(12)]           # f10 sorts after f9, not after f1
    write_images(tmp_path / "seq", a, names=names)
    (tmp_path / "seq" / "notes.txt").write_text("ignored")
    seq = load_sequence(tmp_path / "seq")
    assert seq.input_bits == 8 and seq.frames.dtype == np.uint8 and len(seq.files) == 12
    np.testing.assert_array_equal(seq.frames, a)


def test_png_and_tiff_folders_16_bit(tmp_path):
    a = frames(np.uint16, top=65535)
    write_images(tmp_path / "png", a, "png")
    seq = load_sequence(tmp_path / "png")
    assert seq.input_bits == 16 and seq.frames.dtype == np.uint16
    np.testing.assert_array_equal(seq.frames, a)
    write_images(tmp_path / "tif", a, "tiff")
    np.testing.assert_array_equal(load_sequence(tmp_path / "tif").frames, a)


def test_folder_of_mixed_sizes_is_refused(tmp_path):
    write_images(tmp_path / "s", [frames(np.uint8, t=1, top=255)[0],
                                  np.zeros((7, 5), np.uint8)])
    with pytest.raises(SequenceError, match=(r"^frames of mixed sizes: frame0\.png is 5 x 6 "
                                             r"\(W x H\) but frame1\.png is 5 x 7$")):
        load_sequence(tmp_path / "s")


def test_folder_of_mixed_bit_depths_is_refused(tmp_path):
    write_images(tmp_path / "s", [np.zeros((6, 5), np.uint8), np.zeros((6, 5), np.uint16)])
    with pytest.raises(SequenceError, match=(r"^frames of mixed bit depths: frame0\.png is "
                                             r"8-bit but frame1\.png is 16-bit$")):
        load_sequence(tmp_path / "s")


def test_empty_folder_colour_and_unreadable_images_are_refused(tmp_path):
    (tmp_path / "empty").mkdir()
    (tmp_path / "empty" / "readme.txt").write_text("no frames")
    with pytest.raises(SequenceError, match=whole(
            f"folder {tmp_path / 'empty'} holds no PNG or TIFF frames (.png, .tif, .tiff): the "
            "sequence is empty")):
        load_sequence(tmp_path / "empty")
    (tmp_path / "rgb").mkdir()
    Image.fromarray(np.zeros((6, 5, 3), np.uint8)).save(tmp_path / "rgb" / "a.png")
    with pytest.raises(SequenceError, match=whole(
            f"{tmp_path / 'rgb' / 'a.png'}: image mode 'RGB' is not 8- or 16-bit grayscale (colour, "
            "palette, float and 1-bit images are refused; convert to grayscale L or I;16)")):
        load_sequence(tmp_path / "rgb")
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "a.png").write_bytes(b"not a png at all")
    junk = tmp_path / "junk" / "a.png"
    with pytest.raises(SequenceError, match=whole(f"cannot read image {junk}: ", then=".+")):
        load_sequence(tmp_path / "junk")


def test_multipage_tiff_is_refused(tmp_path):
    (tmp_path / "m").mkdir()
    pages = [Image.fromarray(np.zeros((6, 5), np.uint8)) for _ in range(3)]
    pages[0].save(tmp_path / "m" / "stack.tif", save_all=True, append_images=pages[1:])
    with pytest.raises(SequenceError, match=whole(
            f"{tmp_path / 'm' / 'stack.tif'} holds 3 frames (multi-page); give one frame per file")):
        load_sequence(tmp_path / "m")


def test_missing_unreadable_and_wrong_kind_of_file(tmp_path):
    with pytest.raises(FileNotFoundError, match=whole(f"input {tmp_path / 'nope.npy'} does not exist")):
        load_sequence(tmp_path / "nope.npy")
    (tmp_path / "broken.npy").write_bytes(b"\x93NUMPY garbage")
    # the text after the reason is numpy's own
    with pytest.raises(SequenceError, match=whole(
            f"cannot read {tmp_path / 'broken.npy'} as a .npy array: the file is damaged or "
            "truncated (", then=r".+\)")):
        load_sequence(tmp_path / "broken.npy")
    (tmp_path / "broken.npz").write_bytes(b"PK not a zip")
    with pytest.raises(SequenceError, match=whole(
            f"cannot read {tmp_path / 'broken.npz'} as a .npz archive: ", then=".+")):
        load_sequence(tmp_path / "broken.npz")
    (tmp_path / "x.csv").write_text("1,2")
    with pytest.raises(SequenceError, match=whole(
            f"input {tmp_path / 'x.csv'}: expected a .npy or .npz file or a folder of PNG/TIFF "
            "frames, got a .csv file")):
        load_sequence(tmp_path / "x.csv")
    np.save(tmp_path / "a.npy", frames())
    with pytest.raises(SequenceError, match=whole(
            f"an npz key ('frames') was given but {tmp_path / 'a.npy'} is a .npy file")):
        load_sequence(tmp_path / "a.npy", key="frames")
