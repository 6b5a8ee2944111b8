; A tower a/b/c/d (a on top) to be reversed: d on c on b on a. Optimal: 8 steps —
; b, c and d each move once (2 actions each) and a must leave b (2 more):
; unstack a b, put-down a, unstack b c, stack b a, unstack c d, stack c b, pick-up d, stack d c.
(define (problem reverse4)
  (:domain blocksworld)
  (:objects a b c d)
  (:init (on a b) (on b c) (on c d) (ontable d) (clear a) (handempty))
  (:goal (and (on d c) (on c b) (on b a))))
