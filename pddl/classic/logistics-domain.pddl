; Logistics with action costs: trucks drive within a city (cost = road length),
; airplanes fly between airports (cost 10); loading and unloading cost 1.
(define (domain logistics-costs)
  (:requirements :typing :action-costs :equality)
  (:types truck airplane - vehicle
          package vehicle - physobj
          airport location - place
          city place physobj - object)
  (:predicates (in-city ?loc - place ?city - city) (at ?obj - physobj ?loc - place) (in ?pkg - package ?veh - vehicle))
  (:functions (total-cost) - number (road ?a ?b - place) - number)
  (:action load
    :parameters (?pkg - package ?veh - vehicle ?loc - place)
    :precondition (and (at ?veh ?loc) (at ?pkg ?loc))
    :effect (and (not (at ?pkg ?loc)) (in ?pkg ?veh) (increase (total-cost) 1)))
  (:action unload
    :parameters (?pkg - package ?veh - vehicle ?loc - place)
    :precondition (and (at ?veh ?loc) (in ?pkg ?veh))
    :effect (and (not (in ?pkg ?veh)) (at ?pkg ?loc) (increase (total-cost) 1)))
  (:action drive
    :parameters (?truck - truck ?from ?to - place ?city - city)
    :precondition (and (at ?truck ?from) (in-city ?from ?city) (in-city ?to ?city) (not (= ?from ?to)))
    :effect (and (not (at ?truck ?from)) (at ?truck ?to) (increase (total-cost) (road ?from ?to))))
  (:action fly
    :parameters (?airplane - airplane ?from ?to - airport)
    :precondition (and (at ?airplane ?from) (not (= ?from ?to)))
    :effect (and (not (at ?airplane ?from)) (at ?airplane ?to) (increase (total-cost) 10))))
