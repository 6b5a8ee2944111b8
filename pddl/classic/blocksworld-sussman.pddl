; Sussman's anomaly: C on A; A and B on the table; goal A on B on C. Optimal: 6 steps.
(define (problem sussman)
  (:domain blocksworld)
  (:objects a b c)
  (:init (on c a) (ontable a) (ontable b) (clear c) (clear b) (handempty))
  (:goal (and (on a b) (on b c))))
