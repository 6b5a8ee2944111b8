; One package from a depot in city 1 to an office in city 2. Optimal cost 23 in 10 steps:
; drive t1 ap1→depot1 (2), load (1), drive t1 depot1→ap1 (2), unload (1), load into the
; plane (1), fly ap1→ap2 (10), unload (1), load into t2 (1), drive ap2→office2 (3), unload (1).
(define (problem logistics-2cities)
  (:domain logistics-costs)
  (:objects c1 c2 - city ap1 ap2 - airport depot1 office2 - location
            t1 t2 - truck plane - airplane p - package)
  (:init (in-city ap1 c1) (in-city depot1 c1) (in-city ap2 c2) (in-city office2 c2)
         (at t1 ap1) (at t2 ap2) (at plane ap1) (at p depot1)
         (= (road ap1 depot1) 2) (= (road depot1 ap1) 2) (= (road ap2 office2) 3) (= (road office2 ap2) 3)
         (= (road ap1 ap1) 0) (= (road ap2 ap2) 0) (= (road depot1 depot1) 0) (= (road office2 office2) 0)
         (= (total-cost) 0))
  (:goal (at p office2))
  (:metric minimize (total-cost)))
