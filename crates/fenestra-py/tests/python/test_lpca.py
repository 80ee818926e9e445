"""Local PCA from Python: SortCluster-LPCA equals LPCA exactly, as seed 003 promises."""

import numpy as np
import pytest

import fenestra as fe


def clustered(n=3000, d=24, k=8, dim=2, noise=0.01, seed=4):
    """Rows near k random dim-dimensional affine subspaces."""
    rng = np.random.default_rng(seed)
    means = rng.normal(size=(k, d))
    bases = [np.linalg.qr(rng.normal(size=(d, dim)))[0].T for _ in range(k)]
    which = rng.integers(0, k, size=n)
    coeffs = rng.normal(size=(n, dim))
    rows = means[which] + np.einsum("nj,njd->nd", coeffs, np.stack(bases)[which])
    return (rows + noise * rng.normal(size=(n, d))).astype(np.float32)


def test_sortcluster_lpca_equals_lpca_and_finds_the_subspaces():
    data = clustered()
    sc = fe.lpca.fit(data, 8, schedule="0:5,2:6")
    plain = fe.lpca.fit(data, 8, schedule="0:5,2:6", algorithm="lpca")
    assert np.array_equal(sc.assignments, plain.assignments)
    assert sc.phi == plain.phi
    for a, b in zip(sc.bases, plain.bases):
        assert np.array_equal(a, b)
    assert sc.relative_squared_error < 1e-3
    assert [b.shape for b in sc.bases] == [(2, 24)] * 8
    assert sc.stats["distance_evals"] < plain.stats["distance_evals"]


def test_classify_puts_the_rows_where_the_fit_did():
    data = clustered()
    f = fe.lpca.fit(data, 8, schedule="0:5,2:6")
    assign, dist = f.classify(data)
    assert np.array_equal(assign, f.assignments)
    assert np.allclose(dist, f.distances, rtol=1e-12, atol=1e-12)


def test_the_fit_is_the_same_on_any_number_of_threads():
    data = clustered(n=1500)
    a = fe.lpca.fit(data, 8, schedule="0:4,2:3", threads=1)
    b = fe.lpca.fit(data, 8, schedule="0:4,2:3")
    assert np.array_equal(a.assignments, b.assignments) and a.phi == b.phi


def test_bad_input_is_named():
    with pytest.raises(fe.FenestraError, match="algorithm"):
        fe.lpca.fit(clustered(n=100), 4, algorithm="pca")
    with pytest.raises(fe.FenestraError, match="schedule|dimension"):
        fe.lpca.fit(clustered(n=100), 4, schedule="2:x")
    with pytest.raises(ValueError, match="matrix"):
        fe.lpca.fit(np.zeros(10, np.float32), 2)
