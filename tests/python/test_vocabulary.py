"""mdbrief.Vocabulary and mdbrief.Database: transform, add, query, save and load, and their errors.
A small plain vocabulary is written as DBoW2 text (its words known by construction); a masked
one is trained by mdbrief-train-vocabulary from .npy descriptor files."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import mdbrief

# k = 2, L = 2, 32 bits: nodes 1 (all zero) and 2 (all one) under the root, words 0..3 the
# leaves 3, 4 (under 1) and 5, 6 (under 2), with weights 1, 2, 3, 4.
TEXT_VOCABULARY = """2 2 0 0
0 0 0 0 0 0 0
0 0 255 255 255 255 0
1 1 0 0 0 0 1
1 1 15 0 0 0 2
2 1 255 255 255 255 3
2 1 240 255 255 255 4
"""
WORD_ROWS = np.array([[0, 0, 0, 0], [15, 0, 0, 0], [255, 255, 255, 255], [240, 255, 255, 255]], np.uint8)


@pytest.fixture()
def vocabulary(tmp_path):
    path = tmp_path / "voc.txt"
    path.write_text(TEXT_VOCABULARY)
    return mdbrief.Vocabulary.import_dbow2_text(path)


def test_text_vocabulary_properties(vocabulary):
    assert (vocabulary.bits, vocabulary.branching, vocabulary.depth) == (32, 2, 2)
    assert (vocabulary.word_count, vocabulary.node_count, vocabulary.masked) == (4, 7, False)
    assert vocabulary.weighting == "tf-idf"
    assert [vocabulary.word_weight(w) for w in range(4)] == [1, 2, 3, 4]
    with pytest.raises(IndexError, match="word 4"):
        vocabulary.word_weight(4)


def test_transform_gives_words_bow_and_direct_index(vocabulary):
    rows = WORD_ROWS[[0, 1, 2, 3, 3, 1]]
    rows[4, 0] ^= 0x01  # one bit from word 3's centroid: still word 3
    bow, direct, words = vocabulary.transform(rows, direct_index_depth=1)
    assert words.dtype == np.uint32 and words.tolist() == [0, 1, 2, 3, 3, 1]
    # tf-idf: count * weight, L1-normalised: words 0..3 have 1*1, 2*2, 1*3, 2*4 of 16.
    assert list(bow) == [0, 1, 2, 3]
    assert [bow[w] for w in range(4)] == pytest.approx([1 / 16, 4 / 16, 3 / 16, 8 / 16])
    assert list(direct) == [1, 2]
    assert direct[1].tolist() == [0, 1, 5] and direct[2].tolist() == [2, 3, 4]
    assert vocabulary.words(rows).tolist() == words.tolist()
    bow_empty, direct_empty, words_empty = vocabulary.transform(np.zeros((0, 4), np.uint8))
    assert bow_empty == {} and direct_empty == {} and words_empty.shape == (0,)


def test_transform_refuses_other_widths_and_mask_shapes(vocabulary):
    with pytest.raises(ValueError, match="32"):
        vocabulary.transform(np.zeros((3, 8), np.uint8))
    with pytest.raises(ValueError):
        vocabulary.transform(np.zeros((3, 4), np.uint8), np.zeros((2, 4), np.uint8))
    with pytest.raises(TypeError):
        vocabulary.transform("not descriptors")


def test_save_load_and_text_round_trip(vocabulary, tmp_path):
    vocabulary.save(tmp_path / "voc.mdbvoc")
    loaded = mdbrief.Vocabulary.load(tmp_path / "voc.mdbvoc")
    assert loaded.fingerprint == vocabulary.fingerprint
    assert loaded.words(WORD_ROWS).tolist() == [0, 1, 2, 3]
    loaded.export_dbow2_text(tmp_path / "again.txt")
    again = mdbrief.Vocabulary.import_dbow2_text(tmp_path / "again.txt")
    assert again.fingerprint == vocabulary.fingerprint


def test_bad_vocabulary_files_name_the_file(vocabulary, tmp_path):
    with pytest.raises(FileNotFoundError):
        mdbrief.Vocabulary.load(tmp_path / "missing.mdbvoc")
    vocabulary.save(tmp_path / "voc.mdbvoc")
    data = (tmp_path / "voc.mdbvoc").read_bytes()
    (tmp_path / "cut.mdbvoc").write_bytes(data[:len(data) - 5])
    with pytest.raises(ValueError, match="cut.mdbvoc"):
        mdbrief.Vocabulary.load(tmp_path / "cut.mdbvoc")
    (tmp_path / "foreign.mdbvoc").write_bytes(b"P5\n2 2\n255\n" + bytes(64))
    with pytest.raises(ValueError, match="foreign.mdbvoc"):
        mdbrief.Vocabulary.load(tmp_path / "foreign.mdbvoc")
    (tmp_path / "bad.txt").write_text(TEXT_VOCABULARY.replace("240", "256"))
    with pytest.raises(ValueError, match="bad.txt"):
        mdbrief.Vocabulary.import_dbow2_text(tmp_path / "bad.txt")


def test_database_add_query_save_load(vocabulary, tmp_path):
    db = mdbrief.Database(vocabulary)
    images = [WORD_ROWS[[0, 0, 1]], WORD_ROWS[[2, 3]], WORD_ROWS[[0, 2, 3, 3]]]
    assert [db.add(d) for d in images] == [0, 1, 2]
    assert len(db) == 3 and db.vocabulary.fingerprint == vocabulary.fingerprint
    results = db.query(images[1], max_results=5)
    assert [entry for entry, _ in results] == [1, 2]  # entry 0 shares no word
    assert results[0][1] == pytest.approx(1.0)
    assert 0 < results[1][1] < 1
    assert db.query(images[1], max_results=1) == results[:1]
    bow, _, _ = vocabulary.transform(images[2])
    assert db.entry(2) == pytest.approx(bow)
    assert db.query_bow(bow, max_results=5) == db.query(images[2], max_results=5)
    assert db.add_bow(bow) == 3
    with pytest.raises(IndexError):
        db.entry(4)

    db.save(tmp_path / "db.bin")
    loaded = mdbrief.Database.load(tmp_path / "db.bin", vocabulary)
    assert len(loaded) == 4
    assert loaded.query(images[0], max_results=5) == db.query(images[0], max_results=5)

    other_path = tmp_path / "other.txt"
    other_path.write_text(TEXT_VOCABULARY.replace(" 4\n", " 5\n"))
    other = mdbrief.Vocabulary.import_dbow2_text(other_path)
    with pytest.raises(ValueError, match="db.bin"):
        mdbrief.Database.load(tmp_path / "db.bin", other)
    with pytest.raises(FileNotFoundError):
        mdbrief.Database.load(tmp_path / "missing.bin", vocabulary)


def test_database_refuses_bad_input(vocabulary):
    db = mdbrief.Database(vocabulary)
    with pytest.raises(ValueError, match="word 9"):
        db.add_bow({9: 1.0})
    with pytest.raises(ValueError, match="outside"):
        db.add_bow({-1: 1.0})
    with pytest.raises(ValueError):
        db.add_bow({0: float("nan")})
    with pytest.raises(TypeError):
        db.add_bow([(0, 1.0)])
    with pytest.raises(ValueError):
        db.query(WORD_ROWS, max_results=0)
    with pytest.raises(ValueError):
        db.add(np.zeros((2, 32), np.uint8))
    assert len(db) == 0


def train_masked_vocabulary(tmp_path):
    build = os.environ.get("MDBRIEF_BUILD_DIR")
    tool = pathlib.Path(build or "", "vocabulary", "mdbrief-train-vocabulary")
    if not build or not tool.exists():
        pytest.skip("MDBRIEF_BUILD_DIR (with mdbrief-train-vocabulary) is not set: run through ctest")
    rng = np.random.default_rng(3)
    # tf: random descriptors reach every word from every image, which tf-idf would weigh 0.
    args = [str(tool), "--branching", "3", "--depth", "2", "--seed", "4", "--weighting", "tf",
            "--out", str(tmp_path / "masked.mdbvoc")]
    images = []
    for i in range(4):
        d = rng.integers(0, 256, (60, 32), dtype=np.uint8)
        m = rng.integers(0, 256, (60, 32), dtype=np.uint8) | rng.integers(0, 256, (60, 32), dtype=np.uint8)
        np.save(tmp_path / f"d{i}.npy", d)
        np.save(tmp_path / f"m{i}.npy", m)
        images.append((d, m))
    args += ["--descriptors"] + [str(tmp_path / f"d{i}.npy") for i in range(4)]
    args += ["--masks"] + [str(tmp_path / f"m{i}.npy") for i in range(4)]
    subprocess.run(args, check=True, capture_output=True)
    return mdbrief.Vocabulary.load(tmp_path / "masked.mdbvoc"), images


def test_masked_vocabulary_uses_masks(tmp_path):
    vocabulary, images = train_masked_vocabulary(tmp_path)
    assert vocabulary.masked and vocabulary.bits == 256 and vocabulary.word_count <= 9
    assert vocabulary.weighting == "tf"
    d, m = images[0]
    with_masks = vocabulary.words(d, m)
    assert with_masks.tolist() == vocabulary.transform(d, m)[2].tolist()
    assert with_masks.tolist() != vocabulary.words(d, np.zeros_like(m)).tolist(), "masks change the words"
    db = mdbrief.Database(vocabulary)
    for d, m in images:
        db.add(d, m)
    assert [db.query(d, m, max_results=1)[0][0] for d, m in images] == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="masked"):
        vocabulary.export_dbow2_text(tmp_path / "masked.txt")
