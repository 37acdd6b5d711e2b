//! Exact cells of the right-angled mirror spaces (`bevy_manifold_test_support::coxeter`),
//! checked against group theory and geometry rather than against itself:
//! a word with a relation inserted names the same copy; a word times a
//! short element that moves the domain (seen in the matrices) names
//! another; and among short words, equal normal forms are exactly equal
//! images of the domain's centre.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::coxeter::RightAngledCoxeter;
use glam::{DMat4, DVec4};

fn spaces() -> Vec<(Space, RightAngledCoxeter)> {
    [
        catalog::by_name("mirrored-cube").unwrap(),
        catalog::mirrored_dodecahedron(),
    ]
    .into_iter()
    .map(|s| {
        let g = RightAngledCoxeter::of(&s).expect("right-angled mirrors");
        (s, g)
    })
    .collect()
}

fn random_word(rng: &mut Rng, faces: usize, max_len: usize) -> Vec<usize> {
    let len = rng.below(max_len + 1);
    (0..len).map(|_| rng.below(faces)).collect()
}

/// The element of the crossings `word` as a matrix: the product of the
/// crossing matrices in order.
fn matrix(space: &Space, word: &[usize]) -> DMat4 {
    let g = space.geometry();
    word.iter().fold(DMat4::IDENTITY, |m, &f| {
        isometry::orthonormalize(g, m * space.crossing(f))
    })
}

#[test]
fn only_right_angled_mirror_spaces_have_this_group() {
    for name in ["torus", "seifert-weber", "poincare"] {
        assert!(
            RightAngledCoxeter::of(&catalog::by_name(name).unwrap()).is_none(),
            "{name}"
        );
    }
    for (s, g) in spaces() {
        assert_eq!(g.generators(), s.faces().len());
        // Each face meets 4 others at an edge in the cube (opposite face
        // apart), 5 in the dodecahedron.
        let per_face = if s.faces().len() == 6 { 4 } else { 5 };
        for a in 0..g.generators() {
            let n = (0..g.generators()).filter(|&b| g.commute(a, b)).count();
            assert_eq!(n, per_face, "{} face {a}", s.name());
            assert!(!g.commute(a, a));
        }
    }
}

#[test]
fn a_word_with_a_relation_inserted_reaches_the_same_copy() {
    let mut rng = Rng(7);
    for (s, g) in spaces() {
        let n = g.generators();
        for _ in 0..10_000 {
            let w = random_word(&mut rng, n, 64);
            let at = rng.below(w.len() + 1);
            let a = rng.below(n);
            // A relator: s s, or (s t)^2 for faces meeting at an edge, or a
            // short word and its inverse (mirrors are involutions: the
            // inverse is the reverse).
            let relator: Vec<usize> = match rng.below(3) {
                0 => vec![a, a],
                1 => {
                    let b = (0..n).find(|&b| g.commute(a, b)).expect("a neighbour");
                    vec![a, b, a, b]
                }
                _ => {
                    let u = random_word(&mut rng, n, 6);
                    u.iter().chain(u.iter().rev()).copied().collect()
                }
            };
            let mut v = w.clone();
            v.splice(at..at, relator);
            assert_eq!(g.normal_form(&w), g.normal_form(&v), "{}: {w:?} vs {v:?}", s.name());
        }
    }
}

#[test]
fn a_word_times_an_element_that_moves_the_domain_reaches_another_copy() {
    let mut rng = Rng(11);
    for (s, g) in spaces() {
        let n = g.generators();
        let mut pairs = 0;
        while pairs < 10_000 {
            let w = random_word(&mut rng, n, 64);
            let u = random_word(&mut rng, n, 6);
            // u is not the identity when it moves the domain's centre out
            // of the domain: decided by the matrices (short words, exact
            // enough), not by the rewriting.
            let moved = matrix(&s, &u) * DVec4::W;
            if s.outside_face(moved, 1e-9).is_none() {
                continue;
            }
            pairs += 1;
            let wu: Vec<usize> = w.iter().chain(&u).copied().collect();
            assert_ne!(g.normal_form(&w), g.normal_form(&wu), "{}: {w:?} and {u:?}", s.name());
        }
    }
}

#[test]
fn among_short_words_equal_normal_forms_are_equal_copies() {
    let mut rng = Rng(13);
    for (s, g) in spaces() {
        let geometry = s.geometry();
        let words: Vec<Vec<usize>> = (0..300).map(|_| random_word(&mut rng, g.generators(), 7)).collect();
        let forms: Vec<Vec<u8>> = words.iter().map(|w| g.normal_form(w)).collect();
        let centres: Vec<DVec4> = words
            .iter()
            .map(|w| geometry.normalize_point::<f64>(matrix(&s, w) * DVec4::W))
            .collect();
        let (mut same, mut differ) = (0, 0);
        for i in 0..words.len() {
            for j in i + 1..words.len() {
                let d = geometry.distance::<f64>(centres[i], centres[j]);
                // Distinct copies' centres are at least twice the
                // inradius apart; one copy's, within rounding.
                let equal_copy = d < 1e-6;
                assert!(equal_copy || d > 1.9 * s.inradius(), "{}: {d}", s.name());
                assert_eq!(
                    forms[i] == forms[j],
                    equal_copy,
                    "{}: {:?} {:?}",
                    s.name(),
                    words[i],
                    words[j]
                );
                if equal_copy {
                    same += 1;
                } else {
                    differ += 1;
                }
            }
        }
        assert!(
            same > 100 && differ > 10_000,
            "{}: {same} equal, {differ} distinct",
            s.name()
        );
    }
}

#[test]
fn far_away_and_back_by_another_route_is_home() {
    // 10^6 crossings out along one route, back along a different one
    // (the same faces with every commuting pair swapped where possible,
    // and relators sprinkled in): the normal form is empty.
    let mut rng = Rng(17);
    for (s, g) in spaces() {
        let n = g.generators();
        let out: Vec<usize> = (0..1_000_000).map(|_| rng.below(n)).collect();
        let mut word = g.reduce(&out);
        let far = word.len();
        for &f in out.iter().rev() {
            if rng.below(100) == 0 {
                g.push(&mut word, f);
                g.push(&mut word, f);
            }
            g.push(&mut word, f);
        }
        assert!(word.is_empty(), "{}: {} letters left", s.name(), word.len());
        assert!(far > 1000, "{}: only {far} letters out", s.name());
    }
}
